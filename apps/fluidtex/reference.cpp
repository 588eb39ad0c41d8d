#include "reference.h"

#include <sstream>

namespace fluidtex::cli {

namespace {

/// Text as man(7) shows it literally: backslashes escaped, hyphens as \-
/// (so that options copy as ASCII), and no line starting with a control
/// character ('.' or ').
std::string roff(const std::string& text) {
  std::string out;
  bool line_start = true;
  for (char c : text) {
    if (line_start && (c == '.' || c == '\'')) out += "\\&";
    line_start = c == '\n';
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  return out;
}

std::string plain(const std::string& text) { return text; }

/// How one form marks an option's names and value type up.
struct Markup {
  std::string (*text)(const std::string&);  ///< escapes text for the form
  const char* name_open;
  const char* name_close;
  const char* arg_open;
  const char* arg_close;
};
const Markup kRoff{roff, "\\fB", "\\fR", "\\fI", "\\fR"};
const Markup kMarkdown{plain, "`", "`", "*", "*"};

/// "-i, --input TEXT" marked up for an option, "RUN" for a positional argument.
std::string heading(const CLI::Option& opt, const Markup& m) {
  if (opt.get_positional() && !opt.nonpositional()) return m.arg_open + m.text(opt.get_name(true)) + m.arg_close;
  std::string names;
  std::stringstream split(opt.get_name(false, true));
  for (std::string name; std::getline(split, name, ',');) {
    if (!names.empty()) names += ", ";
    names += m.name_open + m.text(name) + m.name_close;
  }
  const std::string type = opt.get_type_name();
  if (opt.get_type_size() != 0 && !type.empty()) names += " " + (m.arg_open + m.text(type)) + m.arg_close;
  return names;
}

/// Each option of `app` that --help shows: f(option, its default, empty for
/// a flag or an option without one).
template <class F>
void each_option(const CLI::App& app, F&& f) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_group().empty()) continue;
    f(*opt, opt->get_type_size() != 0 ? opt->get_default_str() : std::string());
  }
}

void write_options(std::ostringstream& out, const CLI::App& app) {
  each_option(app, [&](const CLI::Option& opt, const std::string& def) {
    out << ".TP\n" << heading(opt, kRoff) << "\n" << roff(opt.get_description());
    if (!def.empty()) out << " (default: " << roff(def) << ")";
    out << "\n";
  });
}

}  // namespace

std::string man_page(const CLI::App& app, const std::string& version) {
  std::ostringstream out;
  out << ".TH FLUIDTEX 1 \"\" \"" << roff(version) << "\" \"User Commands\"\n";
  out << ".SH NAME\nfluidtex \\- temporally coherent texture on the free surface of a fluid simulation\n";
  out << ".SH SYNOPSIS\n.B fluidtex\n\\fISUBCOMMAND\\fR [\\fIOPTIONS\\fR]\n";
  for (const CLI::App* sub : app.get_subcommands({}))
    out << ".br\n.B fluidtex " << roff(sub->get_name()) << "\n[\\fIOPTIONS\\fR]\n";
  out << ".SH DESCRIPTION\n"
      << roff(app.get_description()) << "\n.PP\n"
      << roff(
             "fluidtex reads a per-frame mesh sequence whose vertices carry velocities (PLY, OBJ, OpenVDB) and "
             "writes, for every frame, a texture atlas and a UV mesh, the texture carried by deformable patches "
             "that move with the liquid. \"fluidtex run\" is the main job; \"fluidtex SUBCOMMAND --help\" lists "
             "the options of one subcommand, as COMMANDS below does.")
      << "\n.SH OPTIONS\n";
  write_options(out, app);
  out << ".SH COMMANDS\n";
  for (const CLI::App* sub : app.get_subcommands({})) {
    out << ".SS \"fluidtex " << roff(sub->get_name()) << "\"\n" << roff(sub->get_description()) << "\n";
    write_options(out, *sub);
  }
  out << ".SH EXIT STATUS\n"
      << ".TP\n.B 0\n"
      << roff("Done (compare: the runs show the same texture).") << "\n"
      << ".TP\n.B 1\n"
      << roff("An internal error (compare: the runs differ).") << "\n"
      << ".TP\n.B 2\n"
      << roff(
             "Bad input, a job that cannot be continued as recorded, or out of memory: one line on stderr names "
             "the file and the problem, and no output is left half-written.")
      << "\n.SH FILES\n"
      << roff(
             "OUT/job.toml (the job: every option, the build, the exemplar's SHA-1, the frames), "
             "OUT/atlas.####.exr, OUT/mesh.####.obj, OUT/state/patches.####.bin, OUT/stats.jsonl.")
      << "\n.SH SEE ALSO\n"
      << roff(
             "Under the installation prefix (/usr for the Debian package): the manual in share/doc/fluidtex "
             "(README.md and docs/), the Slurm and Blender scripts in share/fluidtex/scripts, an example "
             "sequence in share/fluidtex/examples.")
      << "\n";
  return out.str();
}

namespace {

void markdown_options(std::ostringstream& out, const CLI::App& app) {
  each_option(app, [&](const CLI::Option& opt, const std::string& def) {
    std::string help = opt.get_description();
    for (char& c : help)
      if (c == '\n') c = ' ';
    out << "- " << heading(opt, kMarkdown) << ": " << help;
    if (!def.empty()) out << " (default: `" << def << "`)";
    out << "\n";
  });
}

}  // namespace

std::string command_reference(const CLI::App& app) {
  std::ostringstream out;
  out << "# Command reference\n\n"
      << "Every command and option of `fluidtex`, as `fluidtex COMMAND --help` prints them. The build writes this "
         "page from the option tables (`fluidtex --command-reference docs/commands.md`), and a test fails when "
         "the page differs from what the build writes; `man fluidtex` is the same reference.\n\n";
  for (const CLI::App* sub : app.get_subcommands({}))
    out << "- [fluidtex " << sub->get_name() << "](#fluidtex-" << sub->get_name() << "): " << sub->get_description()
        << "\n";
  out << "\n## fluidtex\n\n";
  markdown_options(out, app);
  for (const CLI::App* sub : app.get_subcommands({})) {
    out << "\n## fluidtex " << sub->get_name() << "\n\n" << sub->get_description() << "\n\n";
    markdown_options(out, *sub);
  }
  return out.str();
}

}  // namespace fluidtex::cli
