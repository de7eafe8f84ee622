// npend animate: the chain drawn as it moves, as an animated GIF or an MP4.
#include <fmt/format.h>

#include <optional>

#include "animation.hpp"
#include "chain_options.hpp"
#include "command.hpp"
#include "control_options.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "output_file.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct animate_options {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  cli::control_options control;
  std::string out, fps, trail, size, frames_csv;
};

// The look of the animation from the options; a GIF's default rate is 25 fps, which its
// delays in hundredths of a second play exactly (30 would play at 33.3).
animation_style make_style(const animate_options& o, video_format format) {
  animation_style style;
  style.fps = o.fps.empty() ? (format == video_format::gif ? 25.0 : 30.0)
                            : cli::parse_number(o.fps, "--fps");
  if (!o.trail.empty()) style.trail = cli::parse_number(o.trail, "--trail");
  if (!o.size.empty()) std::tie(style.width, style.height) = parse_frame_size(o.size);
  check_style(style, format);
  return style;
}

// An output file created up front, so that a bad path (or one the other output names too)
// fails before the work.
void open_output(std::optional<cli::atomic_output_file>& file, const std::string& path,
                 std::string_view option) {
  cli::claim_output(path, option);
  try {
    file.emplace(path);
  } catch (const std::runtime_error& e) {
    throw cli::input_error(fmt::format("{}: {}", option, e.what()));
  }
}

int run_animate(const animate_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::any);
  const std::vector<double> x0 = o.start.make_state(c);
  const integration_options options = o.integrator.make_for(c);
  const std::optional<lqr_design> design = o.control.controller_design(c, options.stepper);
  const video_format format = video_format_of(o.out);
  const animation_style style = make_style(o, format);
  const std::size_t frames = frame_count(options.t_end, style.fps);
  require_animation_tools(format);

  // From here on Ctrl-C stops the run at its next step or frame, so the temporary files
  // created below are always removed again.
  cli::terminal_run control;
  std::optional<cli::atomic_output_file> video, csv;
  open_output(video, o.out, "--out");
  if (!o.frames_csv.empty()) open_output(csv, o.frames_csv, "--frames-csv");

  // Integrating, then drawing (and encoding): a frame takes milliseconds to draw, the
  // chain's motion over 1/fps far less to integrate.
  cli::run_control_share integrating(&control, 0, 0.1), rendering(&control, 0.1, 1);
  integration_options sampled = options;
  sampled.control = &integrating;
  const sampled_motion motion =
      sample_motion(c, x0, sampled, style.fps, design ? &*design : nullptr);
  // Thousands of integration steps a second, then tens of frames.
  control.new_pace();
  const bool done =
      !motion.stopped && render_animation(c, motion, style, format, *video, &rendering);
  control.finish();
  if (!done) {
    fmt::print(stderr, "npend animate: interrupted; nothing written to {}\n", o.out);
    return control.exit_code();
  }
  if (csv) {
    csv->write(frames_csv(motion));
    csv->commit();
  }
  fmt::print("{}: {} frames at {:g} fps, {}x{} px, t = 0 .. {:g} s\n", o.out, frames, style.fps,
             style.width, style.height, motion.t.back());
  return 0;
}

}  // namespace

void add_animate_command(CLI::App& app, command_list& commands) {
  auto opts = std::make_shared<animate_options>();
  CLI::App* cmd = app.add_subcommand(
      "animate", "Draw the chain as it moves, into an animated GIF or an MP4 (gnuplot, ffmpeg)");
  opts->chain.add_to(*cmd);
  opts->start.add_to(*cmd);
  opts->integrator.add_to(*cmd);
  opts->control.add_controller_to(*cmd);
  cmd->add_option("--out", opts->out,
                  "The animation: FILE.gif (drawn by gnuplot) or FILE.mp4 (H.264, frames drawn "
                  "by gnuplot and encoded by ffmpeg)")
      ->required();
  cmd->add_option("--fps", opts->fps,
                  "Frames per second of the chain's time, also the playback rate: frame k shows "
                  "t = k/fps (default: 25 for GIF, at most 50; 30 for MP4)");
  cmd->add_option("--trail", opts->trail,
                  "Seconds of the last bob's path drawn behind it, fading (default: 2; 0: none)");
  cmd->add_option("--size", opts->size,
                  "Image size WIDTHxHEIGHT in pixels, each 16..4096, even for MP4 (default: "
                  "640x640)");
  cmd->add_option("--frames-csv", opts->frames_csv,
                  "Also write the frames drawn as CSV: t, H, then x_i, y_i (m, y down) of the "
                  "pivot (i = 0) and the link ends");
  commands.push_back({cmd, [opts] { return run_animate(*opts); }});
}

}  // namespace npend::app
