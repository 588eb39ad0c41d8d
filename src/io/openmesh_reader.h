// OpenMesh's readers (PLYReader, OBJReader) are process-wide singletons
// with per-file state, and omerr/omlog are process-wide streams: every
// OpenMesh read in the library goes through run_openmesh_reader.
#pragma once

#include <mutex>

#include <OpenMesh/Core/System/omstream.hh>

namespace fluidtex {

/// The one lock of all OpenMesh reads (an inline function's static: one
/// object in the program).
inline std::mutex& openmesh_reader_mutex() {
  static std::mutex m;
  return m;
}

/// Runs an OpenMesh reader with its diagnostics silenced. PLYReader and
/// OBJReader are process-wide singletons with per-file state, so concurrent
/// reads are serialised here (parsing is a few ms of a frame's work).
template <typename ReadFn>
bool run_openmesh_reader(ReadFn&& read) {
  std::lock_guard<std::mutex> lock(openmesh_reader_mutex());
  OpenMesh::mostream* streams[] = {&::omerr(), &::omlog(), &::omout()};
  bool was_enabled[3];
  for (int i = 0; i < 3; ++i) {
    was_enabled[i] = streams[i]->is_enabled();
    streams[i]->disable();
  }
  const bool ok = read();
  for (int i = 0; i < 3; ++i)
    if (was_enabled[i]) streams[i]->enable();
  return ok;
}

}  // namespace fluidtex
