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
#include "fluidtex/io/stats.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/pipeline.h"
#include "fluidtex/job/synth_job.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/memory.h"
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

/// A library option (util/options.h) on the command line: its flags, help,
/// section, default and choices, parsed and validated by the library.
CLI::Option* add_table_option(CLI::App* cmd, const OptionRef& ref) {
  const std::string flags = (*ref.info.alias != '\0' ? std::string(ref.info.alias) + "," : "") + "--" + ref.info.name;
  CLI::Option* op = nullptr;
  const auto set = ref.set;
  switch (ref.kind) {
    case OptionRef::Kind::Flag:
      op = cmd->add_flag_callback(
          flags, [set] { set({"true"}); }, ref.info.help);
      break;
    case OptionRef::Kind::Value:
      op = cmd->add_option_function<std::string>(
          flags, [set](const std::string& v) { set({v}); }, ref.info.help);
      if (const std::string d = ref.text(); !d.empty()) op->default_str(d);
      op->type_name(ref.type);
      break;
    case OptionRef::Kind::List:
      op = cmd->add_option_function<std::vector<std::string>>(
                  flags, [set](const std::vector<std::string>& v) { set(v); }, ref.info.help)
               ->delimiter(',')
               ->type_name(ref.type);
      break;
  }
  if (!ref.choices.empty()) op->check(CLI::IsMember(ref.choices));
  if (*ref.info.group != '\0') op->group(ref.info.group);
  return op;
}

/// Options every subcommand reading a sequence shares (--skipped-frames is
/// run's alone). `preview` reads the input only for its overlays: -i is
/// optional there and --frames is its own.
void add_input_options(CLI::App* cmd, InputOptions& in, bool preview = false) {
  InputOptions::for_each_option(in, [&](OptionInfo info, auto& field) {
    const std::string name = info.name;
    if (name == "skipped-frames") return;
    if (preview && name == "frames") return;
    if (preview && name == "input") info.help = "The run's input frame pattern (needed by --overlay)";
    add_table_option(cmd, bind_option(info, field));
  });
}

/// A number from `lo` to `hi`. CLI11's Range lets NaN through ("nan" parses
/// as a double and fails neither comparison); this refuses it.
CLI::Validator number_between(double lo, double hi) {
  const std::string range = format_number(lo) + " to " + format_number(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0.0;
        try {
          std::size_t used = 0;
          v = std::stod(text, &used);
          if (used != text.size()) return "'" + text + "' is not a number";
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        return v >= lo && v <= hi ? std::string() : "must be from " + range + ", not " + text;
      },
      "from " + range);
}

/// --threads of a command that reads or writes frames (0: all cores).
void add_threads_option(CLI::App* cmd, int& threads) {
  cmd->add_option("--threads", threads, "Threads in all, image reading and writing included (0 = all cores)")
      ->check(number_between(0, 4096))
      ->capture_default_str();
}

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
};

/// The options of `run`: the job's table (job/job_options.h), then the
/// console and config options of the command line.
void define_run_options(CLI::App* run, const std::shared_ptr<RunArgs>& args) {
  for (const OptionRef& ref : option_table(args->job)) add_table_option(run, ref);
  for (const OptionRef& ref : args->console.options()) add_table_option(run, ref);
  run->add_option("--config", args->config,
                  "Read options from a TOML file (see --print-config); options given on the command line win");
  run->add_flag("--print-config", args->print_config, "Print the effective configuration as TOML and exit");
}

void add_run(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand("run", "Track patches and synthesise the texture atlas of every frame");
  define_run_options(run, args);
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
    ConsoleArgs console;
    int threads = 0;
  };
  auto args = std::make_shared<SynthArgs>();
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Texture frames of a tracked job (run --track-only) from its states: atlases and UV meshes identical to "
      "fluidtex run's; any number of synth steps may texture different frames at once");
  cmd->add_option("-o,--output", args->request.dir, "The job's output folder (with job.toml and state/)")->required();
  cmd->add_option("--frames", args->request.frames, "Frames to texture, e.g. 7-12 (default: all of the job's)");
  cmd->add_option("-i,--input", args->request.input,
                  "Where this machine sees the job's input frames, when not at the pattern job.toml records "
                  "(checked against each frame's state)");
  cmd->add_option("--velocity-vdb", args->request.velocity_vdb,
                  "Where this machine sees the job's --velocity-vdb frames, when not where job.toml records them");
  cmd->add_option("-e,--exemplar", args->request.exemplar,
                  "Where this machine sees the job's exemplar, when not where job.toml records it (checked by "
                  "content)");
  add_threads_option(cmd, args->threads);
  cmd->add_flag("--prune-state", args->request.prune_state,
                "Remove the textured frames' states once all are written (the job's last state stays, for "
                "run --resume)");
  for (const OptionRef& ref : args->console.options()) add_table_option(cmd, ref);
  cmd->callback([args, &exit_code]() {
    ConsoleReporter reporter = args->console.open_reporter();
    const auto threads = limit_threads(args->threads);
    const JobSummary summary = synth_job(args->request, reporter);
    reporter.info("fluidtex synth: " + std::to_string(summary.frames) + " frames in " +
                  std::to_string(summary.seconds) + " s");
    exit_code = 0;
  });
}

void add_info(CLI::App& app, int& exit_code) {
  auto in = std::make_shared<InputOptions>();
  auto json = std::make_shared<bool>(false);
  CLI::App* info = app.add_subcommand("info", "Describe a mesh sequence and the problems found in it");
  add_input_options(info, *in);
  info->add_flag("--json", *json, "One JSON document on stdout instead of the table (for scripts)");
  info->callback([in, json, &exit_code]() {
    const Sequence sequence(*in);
    std::vector<FrameInfo> frames(sequence.size());
    for (std::size_t i = 0; i < sequence.size(); ++i) frames[i] = inspect_frame(sequence, i);
    if (*json)
      std::cout << format_info_json(frames, sequence.fps(), sequence.fps_source(), in->pattern);
    else
      std::cout << "sequence " << in->pattern << "\n" << format_info(frames, sequence.fps(), sequence.fps_source());
    bool bad = false;
    for (const FrameInfo& f : frames) bad = bad || !f.error.empty();
    exit_code = bad ? 2 : 0;
  });
}

void add_gen(CLI::App& app, int& exit_code) {
  struct GenArgs {
    std::string scene, dir, exemplar;
    SceneOptions scene_options;
    int exemplar_size = 512;
    std::uint64_t seed = 1;
  };
  auto args = std::make_shared<GenArgs>();
  std::string scenes;
  for (const std::string& s : scene_names()) scenes += (scenes.empty() ? "" : ", ") + s;
  std::string exemplars;
  for (const std::string& s : exemplar_names()) exemplars += (exemplars.empty() ? "" : ", ") + s;
  CLI::App* gen = app.add_subcommand("gen", "Write an example scene (PLY or VDB sequence with analytic velocities)");
  gen->add_option("scene", args->scene, "Scene: " + scenes)->required();
  gen->add_option("-o,--output", args->dir, "Output folder (frames are SCENE.####.ply or .vdb)")->required();
  gen->add_option("--frames", args->scene_options.frames, "Number of frames")->capture_default_str();
  gen->add_option("--fps", args->scene_options.fps, "Frames per second")->capture_default_str();
  gen->add_option("--resolution", args->scene_options.resolution,
                  "Mesh density: grid cells (2D) or voxels (3D) across the domain")
      ->capture_default_str();
  gen->add_option("--format", args->scene_options.format,
                  "ply (x y z vx vy vz) or vdb (level set 'surface' and velocity grid 'vel'; 3D scenes: drop, pour)")
      ->check(CLI::IsMember({"ply", "vdb"}))
      ->capture_default_str();
  gen->add_flag("--staggered", args->scene_options.staggered, "vdb: write the velocity as a staggered (MAC) grid");
  gen->add_option("--exemplar", args->exemplar, "Also write a procedural exemplar OUT/NAME.png: " + exemplars);
  gen->add_option("--exemplar-size", args->exemplar_size, "Exemplar size in pixels")->capture_default_str();
  gen->add_option("--seed", args->seed, "Seed of the exemplar")->capture_default_str();
  gen->callback([args, &exit_code]() {
    const std::string pattern = write_scene(args->scene, args->dir, args->scene_options);
    std::cout << "wrote " << args->scene_options.frames << " frames: " << pattern << "\n";
    if (!args->exemplar.empty()) {
      const std::string path = args->dir + "/" + args->exemplar + ".png";
      write_image(path, make_exemplar(args->exemplar, args->exemplar_size, args->seed));
      std::cout << "wrote exemplar: " << path << "\n";
    }
    exit_code = 0;
  });
}

/// Parses --camera EX,EY,EZ,TX,TY,TZ[,FOV] into `render`.
void parse_camera(const std::string& text, RenderOptions& render) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || !std::isfinite(x)) {
      throw InputError("", "--camera: expected EX,EY,EZ,TX,TY,TZ[,FOV] (numbers), got '" + text + "'");
    }
    v.push_back(x);
    start = comma + 1;
  }
  if (v.size() != 6 && v.size() != 7) {
    throw InputError("", "--camera: expected 6 or 7 numbers EX,EY,EZ,TX,TY,TZ[,FOV], got '" + text + "'");
  }
  render.perspective = true;
  render.eye = Vec3(v[0], v[1], v[2]);
  render.target = Vec3(v[3], v[4], v[5]);
  if (v.size() == 7) render.fov_deg = v[6];
}

struct PreviewArgs {
  PreviewOptions options;
  std::string view = enum_name(RenderOptions{}.view), camera;
  std::vector<std::string> overlays;
};

/// preview's overlay options (--overlay and what the overlays read).
void add_preview_overlays(CLI::App* preview, PreviewArgs& args) {
  preview
      ->add_option("--overlay", args.overlays,
                   "Draw over the frames (comma list): borders, states (disk centres by state), velocity (arrows); "
                   "reads the input RUN/job.toml records, or -i")
      ->delimiter(',')
      ->check(CLI::IsMember({"borders", "states", "velocity"}))
      ->group("Overlays");
  add_input_options(preview, args.options.input, true);
  for (const char* name : {"-i", "--fps", "--velocity-attr", "--velocity-from-positions", "--strict"}) {
    preview->get_option(name)->group("Overlays");
  }
  preview
      ->add_option("--velocity-scale", args.options.velocity_scale,
                   "Velocity arrows are v * dt * K long (K frames of motion)")
      ->check(number_between(1e-6, 1e6))
      ->capture_default_str()
      ->group("Overlays");
  preview->add_option("--arrow-spacing", args.options.arrow_spacing, "Pixels between velocity arrows")
      ->check(number_between(1, 16384))
      ->capture_default_str()
      ->group("Overlays");
}

/// `fluidtex preview` once its options are parsed.
void run_preview_command(PreviewArgs& args) {
  PreviewOptions& o = args.options;
  o.render.view = parse_enum<View>(args.view, "view");
  if (!args.camera.empty()) parse_camera(args.camera, o.render);
  auto wants = [&](const char* name) {
    return std::find(args.overlays.begin(), args.overlays.end(), name) != args.overlays.end();
  };
  o.borders = wants("borders"), o.states = wants("states"), o.velocity = wants("velocity");
  const PreviewSummary summary = run_preview(o);
  if (!summary.frame_pattern.empty())
    std::cout << "wrote " << summary.frames << " previews: " << summary.frame_pattern << "\n";
  if (!summary.sheet_path.empty())
    std::cout << "wrote contact sheet of " << summary.sheet_frames << " frames: " << summary.sheet_path << "\n";
}

void add_preview(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<PreviewArgs>();
  CLI::App* preview = app.add_subcommand("preview", "Render a finished run's textured frames to PNG (OUT/preview/)");
  preview->add_option("run", args->options.run_dir, "The output folder of a fluidtex run")->required();
  preview->add_option("--frames", args->options.frames, "Frames to render, e.g. 1-48x8 (default: all)");
  preview->add_option("--view", args->view, "Orthographic view along an axis: top, front, side")
      ->check(CLI::IsMember(enum_choices<View>()))
      ->capture_default_str();
  preview->add_option("--camera", args->camera,
                      "Perspective camera EX,EY,EZ,TX,TY,TZ[,FOV]: eye, target, vertical field of view in "
                      "degrees (default 40); up is +z (+y when looking along z). Replaces --view");
  preview->add_option("--width", args->options.render.width, "Image width in pixels")
      ->check(number_between(1, 16384))
      ->capture_default_str();
  preview
      ->add_option("--height", args->options.render.height,
                   "Image height of the perspective camera (default: width * 3/4; orthographic views "
                   "follow the framing)")
      ->check(number_between(1, 16384));
  preview->add_option("--mesh", args->options.mesh_pattern, "UV mesh pattern, .obj or .ply (default: the run's)");
  preview->add_option("--atlas", args->options.atlas_pattern, "Atlas pattern (default: the run's)");
  add_preview_overlays(preview, *args);
  preview
      ->add_option("--sheet", args->options.sheet,
                   "Also write RUN/preview/sheet.png: every K-th rendered frame in a grid")
      ->group("Contact sheet");
  preview->add_flag("--sheet-only", args->options.sheet_only, "Write the contact sheet only, no per-frame PNGs")
      ->group("Contact sheet");
  preview->callback([args, &exit_code]() {
    run_preview_command(*args);
    exit_code = 0;
  });
}

struct EvalArgs {
  EvalOptions eval;
  std::string view = enum_name(RenderOptions{}.view);
  ConsoleArgs console;
  int threads = 0;
  bool check = false;
  std::string thresholds_file;
};

/// `fluidtex eval` once its options are parsed (`given(name)`: the option
/// --name is on the command line); returns the exit code.
int run_eval_command(EvalArgs& args, const std::function<bool(const std::string&)>& given) {
  ConsoleReporter reporter = args.console.open_reporter();
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
  options.render.view = parse_enum<View>(args.view, "view");
  options.render.width = 384;
  const auto threads = limit_threads(args.threads);
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
  cmd->add_option("-i,--input", args->eval.input.pattern, "The input sequence (default: the run's, from job.toml)");
  cmd->add_option("-o,--output", args->eval.run_dir, "The run's output folder (with job.toml)")->required();
  cmd->add_option("--frames", args->eval.input.frames, "Frames to evaluate (default: the run's)");
  cmd->add_option("-e,--exemplar", args->eval.exemplar, "Exemplar (default: the run's, from job.toml)");
  cmd->add_option("--samples", args->eval.samples, "Warping-error sample points per frame pair")
      ->check(number_between(100, 10000000))
      ->capture_default_str();
  cmd->add_option("--seed", args->eval.seed, "Seed of the sample points")->capture_default_str();
  cmd->add_option("--flow-width", args->eval.flow_width, "Render width for the optical-flow metric (0: skip it)")
      ->check(number_between(0, 8192))
      ->capture_default_str();
  cmd->add_option("--flow-max-motion", args->eval.flow_max_motion,
                  "Projected motion (pixels per frame of the flow renders) from which a pixel is left out of the "
                  "flow_slow_ figures: the optical flow is unreliable beyond")
      ->check(number_between(1e-9, 1e9))
      ->capture_default_str();
  cmd->add_option("--images", args->eval.report_images, "Preview images in the report")
      ->check(number_between(0, 1000))
      ->capture_default_str();
  cmd->add_option("--view", args->view, "Orthographic view of the renders: top, front, side")
      ->check(CLI::IsMember(enum_choices<View>()))
      ->capture_default_str();
  add_threads_option(cmd, args->threads);
  for (const OptionRef& ref : args->console.options()) add_table_option(cmd, ref);
  cmd->add_flag("--check", args->check, "Exit 1 when the verdict is bad (a figure beyond its bad threshold), for CI");
  cmd->add_option("--thresholds", args->thresholds_file,
                  "TOML file of verdict thresholds, in its [eval] table (the options given here win)");
  for (const OptionRef& ref : option_table(args->eval.thresholds)) add_table_option(cmd, ref);
  cmd->callback([args, &exit_code, cmd]() {
    exit_code = run_eval_command(*args, [cmd](const std::string& name) { return cmd->count("--" + name) > 0; });
  });
}

void add_compare(CLI::App& app, int& exit_code) {
  struct CompareArgs {
    CompareOptions compare;
    ConsoleArgs console;
    int threads = 0;
  };
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Compare two runs of the same input where the texture is seen (on the surface, so a different atlas layout is "
      "not a difference); exit 0 same, 1 differs, 2 bad input");
  cmd->add_option("golden", args->compare.golden, "The reference run's output folder")->required();
  cmd->add_option("new", args->compare.candidate, "The run to check")->required();
  cmd->add_option("--samples", args->compare.samples, "Surface points per frame")
      ->check(number_between(100, 10000000))
      ->capture_default_str();
  cmd->add_option("--seed", args->compare.seed, "Seed of the surface points")->capture_default_str();
  cmd->add_option("--mean-tolerance", args->compare.mean_tolerance,
                  "Largest mean colour difference per frame (linear, mean over channels)")
      ->check(number_between(0.0, 1e9))
      ->capture_default_str();
  cmd->add_option("--percentile", args->compare.percentile, "Which percentile of the differences to bound")
      ->check(number_between(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--percentile-tolerance", args->compare.percentile_tolerance,
                  "Largest value of that percentile per frame")
      ->check(number_between(0.0, 1e9))
      ->capture_default_str();
  add_threads_option(cmd, args->threads);
  for (const OptionRef& ref : args->console.options()) add_table_option(cmd, ref);
  cmd->callback([args, &exit_code]() {
    ConsoleReporter reporter = args->console.open_reporter();
    const auto threads = limit_threads(args->threads);
    const Comparison result = compare_runs(args->compare, reporter);
    // -q: the verdict line only.
    std::cout << (args->console.quiet ? comparison_verdict(result, args->compare)
                                      : format_comparison(result, args->compare));
    exit_code = result.passed ? 0 : 1;
  });
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
    // against the machine's (or the farm slot's) memory: the user can fix it.
    print_error("out of memory: lower --atlas-size or --threads, or give the job more memory");
    return 2;
  } catch (const std::exception& e) {
    print_error(e.what(), true);
    return 1;
  }
  return exit_code;
}

}  // namespace fluidtex::cli
