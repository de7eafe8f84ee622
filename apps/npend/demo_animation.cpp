// npend demo: the motions of section 5 as short animations in its folder and index.
#include <fmt/format.h>

#include "animation.hpp"
#include "demo_sections.hpp"
#include "output_file.hpp"
#include "terminal_run.hpp"

namespace npend::app {

std::string add_demo_animation(figure_folder& folder, const chain& c, std::span<const double> x0,
                               const std::string& stem, const std::string& heading,
                               const std::string& text) {
  // Small and short, so that the demo stays quick: 320x320 at 20 fps (a GIF plays 20 fps
  // exactly: its delays are hundredths of a second) over a few seconds.
  constexpr double seconds = 6;
  const animation_style style{.fps = 20, .trail = 1.5, .width = 320, .height = 320};
  integration_options options;
  options.t_end = seconds;
  const auto gif = folder.dir() / (stem + ".gif"), csv = folder.dir() / (stem + "_frames.csv");

  cli::terminal_run control;
  options.control = &control;
  const sampled_motion motion = sample_motion(c, x0, options, style.fps);
  bool drawn = !motion.stopped;
  // Like the demo's plots, an animation gnuplot cannot draw is a note, not a failure.
  try {
    require_animation_tools(video_format::gif);
    cli::atomic_output_file file(gif);
    drawn = drawn && render_animation(c, motion, style, video_format::gif, file, &control);
  } catch (const cli::write_error&) {
    throw;  // a full disk is not a missing tool: the demo fails
  } catch (const std::runtime_error& e) {
    folder.index().notes.push_back(
        fmt::format("{} not drawn: {}", gif.filename().string(), e.what()));
    return {};
  }
  control.finish();
  if (!drawn)
    throw cli::interrupted(
        fmt::format("interrupted while animating; nothing written to {}", gif.string()),
        control.exit_code());
  cli::write_file_atomically(csv, frames_csv(motion));
  folder.record(gif.string());
  folder.record(csv.string());
  folder.index().entries.push_back({.heading = heading,
                                    .image = gif.filename().string(),
                                    .text = text,
                                    .data = {csv.filename().string()},
                                    .scripted = false});
  fmt::print("### {}\n{}\n-> {}\n\n", heading, text, gif.string());
  return gif.string();
}

}  // namespace npend::app
