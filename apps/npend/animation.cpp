#include "animation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include "child_process.hpp"
#include "input_parsing.hpp"
#include "output_file.hpp"
#include "plotting.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

// The colours: the rods dark grey, the bobs blue, the last bob red like its trail, which
// fades into the white background with age.
constexpr std::string_view rod_colour = "#404040";
constexpr std::string_view bar_colour = "#8a9bb0";
constexpr std::string_view bob_colour = "#1f77b4";
constexpr std::string_view last_bob_colour = "#d62728";
constexpr int trail_red = 0xd6, trail_green = 0x27, trail_blue = 0x28;

constexpr std::string_view gnuplot_missing =
    "gnuplot is not installed: it draws the frames (Debian: apt-get install gnuplot-nox)";
constexpr std::string_view ffmpeg_missing =
    "ffmpeg is not installed: it encodes the MP4 (Debian: apt-get install ffmpeg), or write a "
    ".gif";

// Whether the links carry their mass along their length (rods, a centre of mass off the
// end, an inertia): then they are drawn as bars instead of lines with bobs.
bool has_distributed_mass(const chain_parameters& p) {
  for (std::size_t k = 0; k < p.com.size(); ++k)
    if (p.com[k] != p.lengths[k]) return true;
  return std::any_of(p.inertia.begin(), p.inertia.end(), [](double j) { return j > 0; });
}

// The trail colour of a point `age` seconds old: red fading linearly into white, in 16
// shades (a GIF frame has a palette of 256 colours; more shades run out of exact entries and
// come out in stray hues).
int trail_colour(double age, double trail) {
  constexpr double shades = 16;
  const double fade = std::round(std::clamp(age / trail, 0.0, 1.0) * shades) / shades;
  const auto mix = [fade](int channel) {
    return static_cast<int>(std::lround(channel + (255 - channel) * fade));
  };
  return (mix(trail_red) << 16) | (mix(trail_green) << 8) | mix(trail_blue);
}

// Half the width and height of the view (m): the chain at full stretch from wherever the
// drive takes the pivot, with a margin, widened along the longer side of the image so that
// both axes have the same scale.
std::pair<double, double> view_half_extent(const chain_parameters& p, int width, int height) {
  double reach = 0;
  for (double l : p.lengths) reach += l;
  if (p.pivot.moves()) reach += p.pivot.amplitude;
  reach *= 1.08;
  const double aspect = static_cast<double>(width) / height;
  return {reach * std::max(1.0, aspect), reach * std::max(1.0, 1.0 / aspect)};
}

// Line widths, point and font sizes grow with the image (tuned at 320 px).
struct drawing_sizes {
  double scale;
  int font, rod_width, bar_width;
  double bob_size, pivot_size;
};

drawing_sizes sizes_for(const animation_style& style, video_format format) {
  const double scale = std::min(style.width, style.height) / 320.0;
  // libgd draws a point of the same size about 15 % smaller than cairo.
  const double point = format == video_format::gif ? 1.25 : 1.1;
  return {scale,
          std::max(7, static_cast<int>(std::lround(9 * scale))),
          std::max(1, static_cast<int>(std::lround(2 * scale))),
          std::max(3, static_cast<int>(std::lround(8 * scale))),
          1.6 * scale * point,
          1.1 * scale * point};
}

// The gnuplot settings before the first frame: the terminal, and a bare plot area filling
// the image with fixed ranges.
std::string script_preamble(const chain& c, const animation_style& style, video_format format,
                            const std::filesystem::path& gif) {
  const drawing_sizes sizes = sizes_for(style, format);
  std::string s = "set encoding utf8\n";
  if (format == video_format::gif) {
    // A GIF's frame delay is given in hundredths of a second.
    const int delay = static_cast<int>(std::lround(100 / style.fps));
    s += fmt::format(
        "set terminal gif animate delay {} loop 0 size {},{} font \"DejaVuSans,{}\"\n"
        "set output {}\n",
        delay, style.width, style.height, sizes.font, cli::gnuplot_string(gif.string()));
  } else {
    s += fmt::format(
        "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {{\n"
        "  set terminal pngcairo size {},{} font \"DejaVu Sans,{}\"\n"
        "}} else {{\n"
        "  set terminal png size {},{} font \"DejaVuSans,{}\"\n"
        "}}\n",
        style.width, style.height, sizes.font, style.width, style.height, sizes.font);
  }
  const auto [half_width, half_height] =
      view_half_extent(c.parameters(), style.width, style.height);
  s += fmt::format(
      "unset border; unset tics; unset key\n"
      "set lmargin at screen 0; set rmargin at screen 1\n"
      "set bmargin at screen 0; set tmargin at screen 1\n"
      "set xrange [{}:{}]; set yrange [{}:{}]\n",
      -half_width, half_width, -half_height, half_height);
  return s;
}

// One frame: the chain and the trail as data blocks, the caption, and the plot command.
// Gnuplot's y points up; the samples' y points down.
std::string frame_script(const sampled_motion& motion, std::size_t frame, bool bars,
                         const animation_style& style, const drawing_sizes& sizes,
                         video_format format) {
  const std::size_t j = frame * sampled_motion::oversampling;
  const int n = motion.links;
  std::string s = "$chain << EOD\n";
  auto out = std::back_inserter(s);
  for (int i = 0; i <= n; ++i) {
    const auto p = motion.point(j, i);
    fmt::format_to(out, "{:.6g} {:.6g}\n", p[0], -p[1]);
  }
  s += "EOD\n";
  std::string trail_curve;
  if (style.trail > 0 && j > 0) {
    s += "$trail << EOD\n";
    const double since = motion.t[j] - style.trail;
    for (std::size_t i = j + 1; i-- > 0 && motion.t[i] >= since - 1e-12;) {
      const auto p = motion.point(i, n);
      fmt::format_to(out, "{:.6g} {:.6g} {}\n", p[0], -p[1],
                     trail_colour(motion.t[j] - motion.t[i], style.trail));
    }
    s += "EOD\n";
    trail_curve = fmt::format("$trail using 1:2:3 with lines lw {} lc rgb variable, ",
                              std::max(1, static_cast<int>(std::lround(1.5 * sizes.scale))));
  }
  fmt::format_to(out,
                 "set label 1 \"t = {:.2f} s    H = {:.5g} J\" at graph 0.02, graph 0.96 "
                 "left front noenhanced\n",
                 motion.t[j], motion.energy[j]);
  if (format == video_format::mp4) fmt::format_to(out, "set output \"frame_{:06d}.png\"\n", frame);
  const std::string links =
      bars ? fmt::format(
                 "$chain using 1:2 with lines lw {} lc rgb '{}', "
                 "$chain every ::1 using 1:2 with points pt 7 ps {:.2f} lc rgb '{}', ",
                 sizes.bar_width, bar_colour, 0.5 * sizes.bob_size, rod_colour)
           : fmt::format(
                 "$chain using 1:2 with lines lw {} lc rgb '{}', "
                 "$chain every ::1 using 1:2 with points pt 7 ps {:.2f} lc rgb '{}', ",
                 sizes.rod_width, rod_colour, sizes.bob_size, bob_colour);
  fmt::format_to(out,
                 "plot {}{}$chain every ::{}::{} using 1:2 with points pt 7 ps {:.2f} lc rgb "
                 "'{}', $chain every ::0::0 using 1:2 with points pt 5 ps {:.2f} lc rgb 'black'\n",
                 trail_curve, links, n, n, bars ? 0.7 * sizes.bob_size : sizes.bob_size,
                 last_bob_colour, sizes.pivot_size);
  return s;
}

// A failed tool as an error: its name, status and the last line it printed.
std::runtime_error tool_failure(std::string_view tool, std::string_view doing,
                                const cli::program_result& run) {
  const std::string reason = run.last_line();
  return std::runtime_error(fmt::format("{} failed {} (status {}){}{}", tool, doing, run.status,
                                        reason.empty() ? "" : ": ", reason));
}

// Feeds the script to gnuplot frame by frame in `dir` (so its progress is the drawing's);
// false if `control` asked to stop.
bool draw_frames(const chain& c, const sampled_motion& motion, const animation_style& style,
                 video_format format, const std::filesystem::path& dir,
                 const std::filesystem::path& gif, run_control* control) {
  cli::child_process gnuplot({"gnuplot"}, dir, true);
  const drawing_sizes sizes = sizes_for(style, format);
  const bool bars = has_distributed_mass(c.parameters());
  bool fed = gnuplot.write(script_preamble(c, style, format, gif), control);
  const std::size_t frames = motion.frames();
  for (std::size_t k = 0; fed && k < frames; ++k) {
    if (report_progress(control, static_cast<double>(k), static_cast<double>(frames))) {
      fed = false;
      break;
    }
    fed = gnuplot.write(frame_script(motion, k, bars, style, sizes, format), control);
  }
  // The gif terminal writes the file's trailer when its output is closed.
  if (fed) fed = gnuplot.write("set output\n", control);
  const cli::program_result run = gnuplot.finish(control);
  if (stop_requested(control)) return false;
  if (run.status == 127) throw std::runtime_error(std::string(gnuplot_missing));
  if (run.status != 0 || !fed) throw tool_failure("gnuplot", "drawing the frames", run);
  return true;
}

// Encodes the PNG frames in `dir` as H.264 (libx264, yuv420p: what every player takes),
// or as MPEG-4 part 2 where this ffmpeg has no libx264.
bool encode_mp4(const std::filesystem::path& dir, double fps, const std::filesystem::path& mp4,
                run_control* control) {
  cli::program_result run;
  for (const std::vector<std::string>& codec :
       {std::vector<std::string>{"-c:v", "libx264", "-preset", "medium", "-crf", "20"},
        std::vector<std::string>{"-c:v", "mpeg4", "-q:v", "3"}}) {
    std::vector<std::string> argv{
        "ffmpeg", "-nostdin",   "-hide_banner",         "-loglevel", "error",
        "-y",     "-framerate", fmt::format("{}", fps), "-i",        "frame_%06d.png"};
    argv.insert(argv.end(), codec.begin(), codec.end());
    argv.insert(argv.end(), {"-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4",
                             std::filesystem::absolute(mp4).string()});
    run = cli::run_program(argv, dir, control);
    if (stop_requested(control)) return false;
    if (run.status == 0) return true;
    if (run.status == 127) throw std::runtime_error(std::string(ffmpeg_missing));
  }
  throw tool_failure("ffmpeg", "encoding the MP4", run);
}

}  // namespace

video_format video_format_of(const std::filesystem::path& out) {
  std::string extension = out.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (extension == ".gif" && !out.stem().empty()) return video_format::gif;
  if (extension == ".mp4" && !out.stem().empty()) return video_format::mp4;
  throw cli::input_error(
      fmt::format("--out: '{}' must be a file name ending in .gif or .mp4", out.string()));
}

std::pair<int, int> parse_frame_size(const std::string& text) {
  const std::size_t x = text.find('x');
  const auto dimension = [&](const std::string& part) {
    const bool digits = !part.empty() && part.size() <= 5 &&
                        std::all_of(part.begin(), part.end(),
                                    [](unsigned char ch) { return std::isdigit(ch) != 0; });
    const int value = digits ? std::stoi(part) : 0;
    if (value < 16 || value > 4096)
      throw cli::input_error(fmt::format(
          "--size: '{}' is not WIDTHxHEIGHT in pixels, each 16..4096 (e.g. 640x640)", text));
    return value;
  };
  if (x == std::string::npos) dimension("");
  return {dimension(text.substr(0, x)), dimension(text.substr(x + 1))};
}

void check_style(const animation_style& style, video_format format) {
  if (!std::isfinite(style.fps) || style.fps <= 0)
    throw cli::input_error(fmt::format("--fps: must be a positive number, got {}", style.fps));
  if (format == video_format::gif && style.fps > 50)
    throw cli::input_error(fmt::format(
        "--fps: a GIF's frame delay is whole hundredths of a second and players slow down "
        "delays below 2/100 s: at most 50 for a GIF, got {} (write an .mp4 for more)",
        style.fps));
  if (!std::isfinite(style.trail) || style.trail < 0)
    throw cli::input_error(
        fmt::format("--trail: must be a number of seconds >= 0, got {}", style.trail));
  if (format == video_format::mp4 && (style.width % 2 != 0 || style.height % 2 != 0))
    throw cli::input_error(
        fmt::format("--size: an MP4 (yuv420p) needs an even width and height, got {}x{}",
                    style.width, style.height));
}

std::size_t frame_count(double t_end, double fps) {
  const double last = std::floor(t_end * fps + 1e-9);
  if (!(last + 1 <= static_cast<double>(max_frames)))
    throw cli::input_error(fmt::format(
        "--t-end/--fps: {:g} frames is more than the limit of {}; shorten --t-end or lower --fps",
        last + 1, max_frames));
  return static_cast<std::size_t>(last) + 1;
}

sampled_motion sample_motion(const chain& c, std::span<const double> x0,
                             integration_options options, double fps, const lqr_design* design) {
  const int n = c.links();
  sampled_motion m;
  m.links = n;
  m.fps = fps;
  const double rate = fps * sampled_motion::oversampling;
  const std::size_t last = (frame_count(options.t_end, fps) - 1) * sampled_motion::oversampling;
  std::vector<double> xy(static_cast<std::size_t>(2 * n));
  const auto record = [&](double t, std::span<const double> x) {
    m.t.push_back(t);
    m.energy.push_back(c.hamiltonian(x, t));
    c.positions(x.first(static_cast<std::size_t>(n)), xy);
    const auto pivot = c.parameters().pivot.position_at(t);
    m.points.insert(m.points.end(), pivot.begin(), pivot.end());
    for (int k = 0; k < n; ++k) {
      m.points.push_back(pivot[0] + xy[static_cast<std::size_t>(2 * k)]);
      m.points.push_back(pivot[1] + xy[static_cast<std::size_t>(2 * k + 1)]);
    }
  };
  record(0, x0);
  // The grid of dt need not end on the last frame: integrate one step beyond it.
  options.t_end = static_cast<double>(last) / rate + options.dt;
  std::vector<double> x(x0.size());
  std::size_t next = 1;
  const auto sample = [&](const integration_step& step) {
    for (; next <= last; ++next) {
      const double t = static_cast<double>(next) / rate;
      if (t > step.t_end()) break;
      if (t == step.t_end()) {
        record(t, step.x_end());
      } else {
        step.state_at(t, x);
        record(t, x);
      }
    }
    return next > last ? observer_action::stop : observer_action::proceed;
  };
  const integration_result result =
      design != nullptr ? integrate_under_feedback(c, *design, x0, options, {}, sample)
                        : integrate(c, x0, options, {}, sample);
  m.stopped = next <= last && result.stopped;
  return m;
}

std::string frames_csv(const sampled_motion& motion) {
  std::string s = "t,H";
  auto out = std::back_inserter(s);
  for (int i = 0; i <= motion.links; ++i) fmt::format_to(out, ",x_{0},y_{0}", i);
  s += '\n';
  for (std::size_t k = 0; k < motion.frames(); ++k) {
    const std::size_t j = k * sampled_motion::oversampling;
    fmt::format_to(out, "{},{}", motion.t[j], motion.energy[j]);
    for (int i = 0; i <= motion.links; ++i) {
      const auto p = motion.point(j, i);
      fmt::format_to(out, ",{},{}", p[0], p[1]);
    }
    s += '\n';
  }
  return s;
}

void require_animation_tools(video_format format) {
  if (cli::run_program({"gnuplot", "--version"}).status == 127)
    throw std::runtime_error(std::string(gnuplot_missing));
  if (format == video_format::mp4 && cli::run_program({"ffmpeg", "-version"}).status == 127)
    throw std::runtime_error(std::string(ffmpeg_missing));
}

bool render_animation(const chain& c, const sampled_motion& motion, const animation_style& style,
                      video_format format, cli::atomic_output_file& file, run_control* control) {
  // An MP4's progress: drawing, then encoding, which takes about half as long.
  const double drawn = format == video_format::gif ? 1 : 0.7;
  cli::run_control_share drawing(control, 0, drawn), encoding(control, drawn, 1);
  if (format == video_format::gif) {
    if (!draw_frames(c, motion, style, format, ".",
                     std::filesystem::absolute(file.temporary_path()), &drawing))
      return false;
  } else {
    const cli::temporary_folder frames(file.path());
    if (!draw_frames(c, motion, style, format, frames.path(), {}, &drawing)) return false;
    encoding.progress(0, 1);
    if (!encode_mp4(frames.path(), style.fps, file.temporary_path(), &encoding)) return false;
  }
  // The tools wrote the temporary file by its name, and exit with 0 even when a full disk or
  // the file-size limit cut it short: check it, then commit syncs and renames it.
  cli::check_written_image(
      file.temporary_path(), file.path(),
      format == video_format::gif ? cli::image_format::gif : cli::image_format::mp4);
  file.commit();
  return true;
}

}  // namespace npend::app
