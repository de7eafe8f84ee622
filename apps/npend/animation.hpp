// Animations of a chain's motion (npend animate, npend demo): the chain sampled from the
// integrator at the frame times, drawn frame by frame by gnuplot, and encoded as an animated
// GIF (gnuplot's gif terminal) or an MP4 (PNG frames encoded by ffmpeg).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "npend/analysis/stability/lqr.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/run_control.hpp"
#include "output_file.hpp"

namespace npend::app {

enum class video_format { gif, mp4 };

/// The format an output path asks for by its extension (.gif or .mp4, any case); throws
/// input_error naming --out otherwise.
video_format video_format_of(const std::filesystem::path& out);

/// How the animation looks.
struct animation_style {
  double fps = 25;                ///< frames per second of the chain's time (and of playback)
  double trail = 2;               ///< seconds of the last bob's path drawn behind it; 0: none
  int width = 640, height = 640;  ///< pixels
};

/// "WxH" (pixels, each 16..4096) as width and height; throws input_error naming --size.
std::pair<int, int> parse_frame_size(const std::string& text);

/// Checks the style against the format (throws input_error naming the option): fps > 0
/// and finite, at most 50 for a GIF (its frame delays are whole hundredths of a second,
/// and players slow down delays below 2/100 s); trail ≥ 0; an even size for an MP4
/// (yuv420p halves the colour resolution).
void check_style(const animation_style& style, video_format format);

/// The number of frames of a run of `t_end` seconds at `fps`: t_k = k/fps for every
/// t_k ≤ t_end (within 1e-9 of a frame), including t_0 = 0. Throws input_error above
/// max_frames.
std::size_t frame_count(double t_end, double fps);
inline constexpr std::size_t max_frames = 100'000;

/// The motion as the animation shows it: the chain at the sample times t_j = j/(S·fps),
/// S = oversampling, of which every S-th is a frame (t_k = k/fps exactly: S is a power of
/// two, so the division rounds alike); the samples between frames draw the trail.
struct sampled_motion {
  static constexpr int oversampling = 4;

  int links = 0;
  double fps = 0;
  std::vector<double> t;       ///< sample times (s)
  std::vector<double> energy;  ///< H(x(t), t) at each sample (J)
  /// Per sample the pivot and the link ends, (n + 1) points (x, y) in m, y pointing down,
  /// in the lab frame (the pivot where its drive has moved it).
  std::vector<double> points;
  bool stopped = false;  ///< the run control stopped the integration

  std::size_t samples() const { return t.size(); }
  /// Frames: the samples j = 0, S, 2S, …
  std::size_t frames() const { return (samples() + oversampling - 1) / oversampling; }
  /// Point i (0: pivot, k: end of link k) of sample j: {x, y}.
  std::span<const double, 2> point(std::size_t j, int i) const {
    return std::span<const double, 2>(
        points.data() + (j * static_cast<std::size_t>(links + 1) + static_cast<std::size_t>(i)) * 2,
        2);
  }
};

/// Integrates `c` from x0 (dim 2n) with `options` (t_start = 0, forward) — under the LQR
/// feedback of `design` if given (npend simulate --controller) — and samples it at the
/// frame times up to options.t_end and in between for the trail: the integrator's own state
/// where a sample falls on the end of a step, its dense output (integration_step::state_at)
/// inside a step. Throws what npend::integrate throws.
sampled_motion sample_motion(const chain& c, std::span<const double> x0,
                             integration_options options, double fps,
                             const lqr_design* design = nullptr);

/// The frames as CSV: header t,H,x_0,y_0,x_1,y_1,..,x_n,y_n (point 0 the pivot, y down, m),
/// one row per frame, numbers in the shortest form that reads back exactly.
std::string frames_csv(const sampled_motion& motion);

/// Draws the frames with gnuplot and encodes them in `format` into `file`: rods as lines
/// and bobs as dots (bars for links with distributed mass: --rods, --com, --inertia), the
/// pivot where it is, the last bob's fading trail, t and H in the top left corner; fixed
/// axes (the chain's length plus the drive's amplitude) with equal scales. The tools write
/// the file's temporary sibling, and commit() puts it in place only when complete; MP4
/// frames go to a temporary folder next to it, removed afterwards. Progress and stop
/// requests go through `control` (may be null).
///
/// Returns false, having committed nothing, when `control` asked to stop. Throws
/// std::runtime_error when gnuplot or ffmpeg fails (naming the tool and its reason), or the
/// output cannot be written or comes out incomplete (cli::check_written_image).
bool render_animation(const chain& c, const sampled_motion& motion, const animation_style& style,
                      video_format format, cli::atomic_output_file& file, run_control* control);

/// Throws std::runtime_error if a program the format needs (gnuplot; for MP4 also ffmpeg)
/// is not installed, saying what to install.
void require_animation_tools(video_format format);

}  // namespace npend::app
