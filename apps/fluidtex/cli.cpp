#include "cli.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <clocale>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <locale>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <thread>

#include <oneapi/tbb/global_control.h>

#include "fluidtex/inspect/compare.h"
#include "fluidtex/inspect/eval.h"
#include "fluidtex/inspect/info.h"
#include "fluidtex/inspect/overlays.h"
#include "fluidtex/inspect/preview.h"
#include "fluidtex/inspect/render.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/job/synth_job.h"
#include "fluidtex/scenes/example.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/json.h"
#include "fluidtex/util/memory.h"
#include "fluidtex/util/shared_options.h"
#include "fluidtex/util/version.h"
#include "reference.h"

namespace fluidtex::cli {

namespace {

/// How messages reach stderr: plain lines, or one JSON object per line
/// (--log-format json) for farm log collectors.
enum class LogFormat { Text, Json };
inline constexpr EnumName<LogFormat> kLogFormatNames[] = {{LogFormat::Text, "text"}, {LogFormat::Json, "json"}};
constexpr const auto& enum_names(LogFormat) { return kLogFormatNames; }

/// The format of the error line main() prints (set by the command's options).
LogFormat error_format = LogFormat::Text;

std::string json_event(const char* event, const std::string& fields) {
  return std::string("{\"event\":\"") + event + "\"" + fields + "}";
}

/// Messages on stderr. On a terminal, a single refreshing progress line;
/// off a terminal (a farm log) or with --log-format json, one line per
/// finished frame instead. -q keeps warnings (and errors) only.
class ConsoleReporter : public Reporter {
 public:
  ConsoleReporter(int verbosity, bool quiet, LogFormat format)
      : verbosity_(verbosity), quiet_(quiet), format_(format), tty_(::isatty(STDERR_FILENO) != 0),
        start_(std::chrono::steady_clock::now()) {}
  ~ConsoleReporter() override { clear_line(); }

  // Pipeline stages call from several threads.
  void info(const std::string& m) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!quiet_) message("info", m);
  }
  void verbose(const std::string& m) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!quiet_ && verbosity_ > 0) message("verbose", m);
  }
  void warn(const std::string& m) override {
    std::lock_guard<std::mutex> lock(mutex_);
    message("warning", m);
  }
  void frame_done(const FrameReport& r) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (quiet_ || (tty_ && format_ == LogFormat::Text && verbosity_ == 0)) return;
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", r.seconds);
    if (format_ == LogFormat::Json) {
      std::string fields =
          ",\"step\":\"" + std::string(r.step) + "\",\"frame\":" + std::to_string(r.frame) + ",\"seconds\":" + seconds;
      if (r.patches >= 0) fields += ",\"patches\":" + std::to_string(r.patches);
      print(json_event("frame", fields));
      return;
    }
    std::string line = r.step + std::string(" frame ") + std::to_string(r.frame) + ": " + seconds + " s";
    if (r.patches >= 0) line += ", " + std::to_string(r.patches) + " patches";
    print(line);
  }
  void progress(std::size_t done, std::size_t total, const std::string& stage) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (quiet_ || !tty_ || format_ != LogFormat::Text || total == 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double eta = done > 0 ? elapsed / static_cast<double>(done) * static_cast<double>(total - done) : 0.0;
    char line[160];
    std::snprintf(line, sizeof line, "\r\033[Kframe %zu/%zu  %-10s elapsed %s  ETA %s", done, total, stage.c_str(),
                  clock_text(elapsed).c_str(), done > 0 ? clock_text(eta).c_str() : "--:--");
    std::fputs(line, stderr);
    std::fflush(stderr);
    line_shown_ = true;
  }

 private:
  static std::string clock_text(double seconds) {
    const long s = static_cast<long>(seconds + 0.5);
    char buf[32];
    if (s >= 3600)
      std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
      std::snprintf(buf, sizeof buf, "%02ld:%02ld", s / 60, s % 60);
    return buf;
  }
  void clear_line() {
    if (line_shown_) std::fputs("\r\033[K", stderr);
    line_shown_ = false;
  }
  void message(const char* level, const std::string& m) {
    if (format_ == LogFormat::Json)
      print(json_event(level, ",\"message\":" + json_string(m)));
    else
      print(std::string(level) == "warning" ? "warning: " + m : m);
  }
  void print(const std::string& m) {
    clear_line();
    std::fprintf(stderr, "%s\n", m.c_str());
    std::fflush(stderr);
  }
  std::mutex mutex_;
  int verbosity_;
  bool quiet_;
  LogFormat format_;
  bool tty_;
  bool line_shown_ = false;
  std::chrono::steady_clock::time_point start_, last_{};
};

/// The console options of the commands a farm runs: -v, -q, --log-format.
struct ConsoleArgs {
  bool verbose = false;
  bool quiet = false;
  LogFormat log_format = LogFormat::Text;
  std::vector<OptionRef> options() {
    return {bind_option({.name = "verbose", .help = "More detail on stderr", .alias = "-v"}, verbose),
            bind_option({.name = "quiet", .help = "Only warnings and errors", .alias = "-q"}, quiet),
            bind_option({.name = "log-format",
                         .help = "text, or json: one JSON object per line on stderr (frames, messages, the error)"},
                        log_format)};
  }
  /// The reporter of the command; from now on main()'s error line follows
  /// --log-format too.
  ConsoleReporter open_reporter() const {
    error_format = log_format;
    return ConsoleReporter(verbose ? 1 : 0, quiet, log_format);
  }
};

/// Whether the option's value is inside its bounds (a default outside them
/// means "not given", e.g. a height that follows the width).
bool within_bounds(const OptionRef& ref) {
  try {
    ref.check();
    return true;
  } catch (const InputError&) {
    return false;
  }
}

/// A library option (util/options.h) on the command line: its flags, help,
/// section, default and choices, parsed and validated by the library as it
/// is given.
CLI::Option* add_table_option(CLI::App* cmd, const OptionRef& ref) {
  const OptionInfo& info = ref.info;
  const std::string flags = info.positional
                                ? std::string(info.name)
                                : (*info.alias != '\0' ? std::string(info.alias) + "," : "") + "--" + info.name;
  CLI::Option* op = nullptr;
  const auto set = [set = ref.set, check = ref.check](const std::vector<std::string>& values) {
    set(values);
    check();
  };
  switch (ref.kind) {
    case OptionRef::Kind::Flag:
      op = cmd->add_flag_callback(
          flags, [set] { set({"true"}); }, info.help);
      break;
    case OptionRef::Kind::Value:
      op = cmd->add_option_function<std::string>(
          flags, [set](const std::string& v) { set({v}); }, info.help);
      op->type_name(ref.type);
      break;
    case OptionRef::Kind::List:
      op = cmd->add_option_function<std::vector<std::string>>(flags, set, info.help)
               ->delimiter(',')
               ->type_name(ref.type);
      break;
  }
  // The default is shown unless it is a "not given" value outside the bounds.
  if (ref.kind == OptionRef::Kind::Value && !info.positional) {
    if (const std::string d = ref.text(); !d.empty() && within_bounds(ref)) op->default_str(d);
  }
  if (!ref.choices.empty()) op->check(CLI::IsMember(ref.choices));
  if (*info.group != '\0') op->group(info.group);
  if (info.required) op->required();
  return op;
}

/// f(OptionInfo, field) for `for_each_option`: each option onto `cmd`.
auto onto(CLI::App* cmd) {
  return [cmd](const OptionInfo& info, auto& field) { add_table_option(cmd, bind_option(info, field)); };
}

void add_options(CLI::App* cmd, const std::vector<OptionRef>& table) {
  for (const OptionRef& ref : table) add_table_option(cmd, ref);
}

/// The options of a command a farm runs, beside its own: --threads and the
/// console's.
struct FarmArgs {
  int threads = 0;
  ConsoleArgs console;
  std::vector<OptionRef> options() {
    std::vector<OptionRef> table = {bind_option(shared_options::kThreads, threads)};
    for (OptionRef& ref : console.options()) table.push_back(std::move(ref));
    return table;
  }
};

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  limit_image_io_threads(threads);
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(threads));
}

struct RunArgs {
  JobOptions job;
  ConsoleArgs console;
  bool print_config = false;
  std::string config;
  /// The command line's own options: the config file.
  std::vector<OptionRef> options() {
    return {bind_option({.name = "config",
                         .help = "Read options from a TOML file (see --print-config); options given on the command "
                                 "line win"},
                        config),
            bind_option({.name = "print-config", .help = "Print the effective configuration as TOML and exit"},
                        print_config)};
  }
};

void add_run(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand("run", "Track patches and synthesise the texture atlas of every frame");
  // The job's table (job/job_options.h), then the console and config options.
  add_options(run, option_table(args->job));
  add_options(run, args->console.options());
  add_options(run, args->options());
  run->callback([run, args, &exit_code]() {
    if (!args->config.empty()) {
      // CLI11 2.1 does not read a subcommand's own config file before its
      // callback: the library applies it to what the command line left unset.
      const auto given = [run](const std::string& name) {
        const CLI::Option* op = run->get_option_no_throw("--" + name);
        return op != nullptr && op->count() > 0;
      };
      apply_job_file(args->job, args->config, given, args->console.options());
    }
    if (args->print_config) {
      std::cout << job_toml(args->job);
      exit_code = 0;
      return;
    }
    ConsoleReporter reporter = args->console.open_reporter();
    const auto threads = limit_threads(args->job.threads);
    const JobSummary summary = run_job(args->job, reporter);
    reporter.info("fluidtex: " + std::to_string(summary.frames) + " frames in " + std::to_string(summary.seconds) +
                  " s");
    exit_code = 0;
  });
}

void add_synth(CLI::App& app, int& exit_code) {
  struct SynthArgs {
    SynthRequest request;
    FarmArgs farm;
  };
  auto args = std::make_shared<SynthArgs>();
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Texture frames of a tracked job (run --track-only) from its states: atlases and UV meshes identical to "
      "fluidtex run's; any number of synth steps may texture different frames at once");
  SynthRequest::for_each_option(args->request, onto(cmd));
  add_options(cmd, args->farm.options());
  cmd->callback([args, &exit_code]() {
    ConsoleReporter reporter = args->farm.console.open_reporter();
    const auto threads = limit_threads(args->farm.threads);
    const JobSummary summary = synth_job(args->request, reporter);
    reporter.info("fluidtex synth: " + std::to_string(summary.frames) + " frames in " +
                  std::to_string(summary.seconds) + " s");
    exit_code = 0;
  });
}

void add_info(CLI::App& app, int& exit_code) {
  struct InfoArgs {
    InputOptions input;
    bool json = false;
  };
  auto args = std::make_shared<InfoArgs>();
  CLI::App* info = app.add_subcommand("info", "Describe a mesh sequence and the problems found in it");
  const auto add = onto(info);
  add(shared_options::kInput, args->input.pattern);
  add(shared_options::kFrames, args->input.frames);
  InputOptions::for_each_reading_option(args->input, add);
  add({.name = "json", .help = "One JSON document on stdout instead of the table (for scripts)"}, args->json);
  info->callback([args, &exit_code]() {
    const InputOptions& in = args->input;
    const Sequence sequence(in);
    std::vector<FrameInfo> frames(sequence.size());
    for (std::size_t i = 0; i < sequence.size(); ++i) frames[i] = inspect_frame(sequence, i);
    if (args->json)
      std::cout << format_info_json(frames, sequence.fps(), sequence.fps_source(), in.pattern);
    else
      std::cout << "sequence " << in.pattern << "\n" << format_info(frames, sequence.fps(), sequence.fps_source());
    bool bad = false;
    for (const FrameInfo& f : frames) bad = bad || !f.error.empty();
    exit_code = bad ? 2 : 0;
  });
}

void add_gen(CLI::App& app, int& exit_code) {
  auto request = std::make_shared<ExampleRequest>();
  CLI::App* gen = app.add_subcommand("gen", "Write an example scene (PLY or VDB sequence with analytic velocities)");
  ExampleRequest::for_each_option(*request, onto(gen));
  gen->callback([request, &exit_code]() {
    const ExampleFiles files = write_example(*request);
    std::cout << "wrote " << request->scene_options.frames << " frames: " << files.frame_pattern << "\n";
    if (!files.exemplar.empty()) std::cout << "wrote exemplar: " << files.exemplar << "\n";
    exit_code = 0;
  });
}

void add_preview(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<PreviewOptions>();
  CLI::App* preview = app.add_subcommand("preview", "Render a finished run's textured frames to PNG (OUT/preview/)");
  PreviewOptions::for_each_option(*options, onto(preview));
  preview->callback([options, &exit_code]() {
    const PreviewSummary summary = run_preview(*options);
    if (!summary.frame_pattern.empty())
      std::cout << "wrote " << summary.frames << " previews: " << summary.frame_pattern << "\n";
    if (!summary.sheet_path.empty())
      std::cout << "wrote contact sheet of " << summary.sheet_frames << " frames: " << summary.sheet_path << "\n";
    exit_code = 0;
  });
}

struct EvalArgs {
  EvalOptions eval;
  FarmArgs farm;
  bool check = false;
  std::string thresholds_file;
  /// The command line's own options: the verdict's use in CI.
  std::vector<OptionRef> options() {
    return {bind_option(
                {.name = "check", .help = "Exit 1 when the verdict is bad (a figure beyond its bad threshold), for CI"},
                check),
            bind_option({.name = "thresholds",
                         .help = "TOML file of verdict thresholds, in its [eval] table (the options given here win)"},
                        thresholds_file)};
  }
};

/// `fluidtex eval` once its options are parsed (`given(name)`: the option
/// --name is on the command line); returns the exit code.
int run_eval_command(EvalArgs& args, const std::function<bool(const std::string&)>& given) {
  ConsoleReporter reporter = args.farm.console.open_reporter();
  if (!args.thresholds_file.empty()) {
    apply_config(read_config_file(args.thresholds_file, "eval"), option_table(args.eval.thresholds),
                 args.thresholds_file, given);
  }
  args.eval.thresholds.validate();
  const JobOptions job = read_job_manifest(args.eval.run_dir);
  EvalOptions options = args.eval;
  // Input settings as the run read the sequence; the pattern (and frames) given here.
  const std::string pattern = options.input.pattern, frames = options.input.frames;
  options.input = job.input;
  if (!pattern.empty()) options.input.pattern = pattern;
  if (!frames.empty()) options.input.frames = frames;
  options.render.width = 384;
  const auto threads = limit_threads(args.farm.threads);
  const EvalSummary summary = run_eval(options, job, reporter);
  reporter.info("fluidtex eval: " + std::to_string(summary.frames) + " frames; report: " + summary.report);
  const std::string verdict = "verdict: " + summary.verdict.line;
  if (summary.verdict.grade == Grade::Good)
    reporter.info(verdict);
  else
    reporter.warn(verdict);
  for (const VerdictRange& r : summary.verdict.ranges) reporter.warn(r.line);
  return args.check && summary.verdict.grade == Grade::Bad ? 1 : 0;
}

void add_eval(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd =
      app.add_subcommand("eval",
                         "Measure a finished run: coverage, ghosting, patch life, distortion, texture-flow agreement, "
                         "contrast, spectrum (OUT/eval/metrics.jsonl, summary.json, report.html)");
  EvalOptions::for_each_option(args->eval, onto(cmd));
  add_options(cmd, args->farm.options());
  add_options(cmd, args->options());
  add_options(cmd, option_table(args->eval.thresholds));
  cmd->callback([args, &exit_code, cmd]() {
    exit_code = run_eval_command(*args, [cmd](const std::string& name) { return cmd->count("--" + name) > 0; });
  });
}

void add_compare(CLI::App& app, int& exit_code) {
  struct CompareArgs {
    CompareOptions compare;
    FarmArgs farm;
  };
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Compare two runs of the same input where the texture is seen (on the surface, so a different atlas layout is "
      "not a difference); exit 0 same, 1 differs, 2 bad input");
  CompareOptions::for_each_option(args->compare, onto(cmd));
  add_options(cmd, args->farm.options());
  cmd->callback([args, &exit_code]() {
    ConsoleReporter reporter = args->farm.console.open_reporter();
    const auto threads = limit_threads(args->farm.threads);
    const Comparison result = compare_runs(args->compare, reporter);
    // -q: the verdict line only.
    std::cout << (args->farm.console.quiet ? comparison_verdict(result, args->compare)
                                           : format_comparison(result, args->compare));
    exit_code = result.passed ? 0 : 1;
  });
}

/// What to lower when the command `app` ran out of memory: the options that
/// size its largest buffers.
std::string memory_advice(const CLI::App& app) {
  const std::vector<CLI::App*> used = app.get_subcommands();
  const std::string name = used.empty() ? std::string() : used.front()->get_name();
  if (name == "preview") return "lower --width";
  if (name == "eval") return "lower --flow-width, --samples or --threads";
  if (name == "compare") return "lower --samples";
  return "lower --atlas-size or --threads";
}

}  // namespace

void print_error(const std::string& message, bool internal) {
  if (error_format == LogFormat::Json) {
    const std::string line = json_event("error", std::string(",\"internal\":") + (internal ? "true" : "false") +
                                                     ",\"message\":" + json_string(message));
    std::fprintf(stderr, "%s\n", line.c_str());
  } else {
    std::fprintf(stderr, "fluidtex: %s: %s\n", internal ? "internal error" : "error", message.c_str());
  }
}

void add_subcommands(CLI::App& app, int& exit_code) {
  // In the order a user needs them.
  add_run(app, exit_code);
  add_synth(app, exit_code);
  add_info(app, exit_code);
  add_eval(app, exit_code);
  add_compare(app, exit_code);
  add_preview(app, exit_code);
  add_gen(app, exit_code);
  app.footer(
      "Examples:\n"
      "  fluidtex info -i 'sim/surface.####.ply'                             what a sequence holds\n"
      "  fluidtex run -i 'sim/surface.####.ply' -e exemplar.png -o out        texture every frame\n"
      "  fluidtex eval -o out                                                measure it: out/eval/report.html\n"
      "\n"
      "fluidtex COMMAND --help lists a command's options; the manual: man fluidtex, and docs/ (README.md).");
}

int run_command_line(int argc, char** argv) {
  keep_freed_memory_for_reuse();
  std::setlocale(LC_ALL, "C");
  std::locale::global(std::locale::classic());
  CLI::App app{
      "fluidtex: temporally coherent texture synthesis on the free surface of fluids\n"
      "(deformable patches, Gagnon et al. 2019)",
      "fluidtex"};
  int exit_code = 0;
  try {
    app.require_subcommand(1);
    app.set_version_flag("--version", version_line());
    add_subcommands(app, exit_code);
    // Hidden (no group): the build writes fluidtex(1) with it.
    app.add_option_function<std::string>(
           "--man-page",
           [&app](const std::string& path) {
             write_text_atomically(path, man_page(app, version_line()));
             throw CLI::Success();
           },
           "Write the manual page to FILE")
        ->group("");
    app.add_option_function<std::string>(
           "--command-reference",
           [&app](const std::string& path) {
             write_text_atomically(path, command_reference(app));
             throw CLI::Success();
           },
           "Write docs/commands.md to FILE")
        ->group("");
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, like every other error (CLI11 would add "Run with --help ...").
    std::fprintf(stderr, "fluidtex: error: %s (see --help)\n", e.what());
    return 2;
  } catch (const InputError& e) {
    print_error(e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    // Input sizes are bounded where they are read, so this is the job's size
    // against the machine's (or the farm slot's) memory: the user can fix it,
    // with the option that sizes the command's largest buffers.
    print_error("out of memory: " + memory_advice(app) + ", or give the job more memory");
    return 2;
  } catch (const std::exception& e) {
    print_error(e.what(), true);
    return 1;
  }
  return exit_code;
}

}  // namespace fluidtex::cli
