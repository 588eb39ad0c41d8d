# CTest Docs.CommandReferenceIsCurrent: docs/commands.md is what the build's
# `fluidtex --command-reference` writes from the option tables. Fails with
# the command that brings the page up to date.
#   cmake -DEXE=path/to/fluidtex -DSOURCE_DIR=... -DOUT=... -P check_reference.cmake
execute_process(COMMAND ${EXE} --command-reference ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fluidtex --command-reference failed (${rc})")
endif()
file(READ ${OUT} written)
file(READ ${SOURCE_DIR}/docs/commands.md checked_in)
if(NOT written STREQUAL checked_in)
  message(FATAL_ERROR "docs/commands.md differs from the option tables: run "
                      "'build/fluidtex --command-reference docs/commands.md' and commit it")
endif()
