// `npend animate` as a user runs it: the GIF's and the MP4's format, frame count and size,
// frames drawn at the integrator's states (the --frames-csv table against an independent
// integration, and the last bob's pixels in a decoded frame), and bad input, a missing
// tool and Ctrl-C leaving no file.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "npend/integrators/integrate.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;
using npend::test::run_shell;

namespace {

std::vector<unsigned char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// What the GIF's block structure holds: the logical screen's size, the images and the
// graphic control extensions (one per frame of an animation), and whether the trailer ends
// it. Parsed block by block (GIF89a spec): a byte count that runs past the end fails.
struct gif_summary {
  bool valid = false;
  int width = 0, height = 0;
  int images = 0, graphic_controls = 0;
};

gif_summary parse_gif(const std::vector<unsigned char>& b) {
  gif_summary g;
  std::size_t at = 0;
  const auto need = [&](std::size_t count) { return at + count <= b.size(); };
  const auto u16 = [&](std::size_t i) { return b[i] | (b[i + 1] << 8); };
  // Sub-blocks: a size byte, that many bytes, until a size of 0.
  const auto skip_sub_blocks = [&] {
    while (need(1)) {
      const std::size_t size = b[at++];
      if (size == 0) return true;
      if (!need(size)) return false;
      at += size;
    }
    return false;
  };
  if (!need(13) || std::string(b.begin(), b.begin() + 6) != "GIF89a") return g;
  g.width = u16(6);
  g.height = u16(8);
  const unsigned char flags = b[10];
  at = 13;
  if (flags & 0x80) at += 3u * (1u << ((flags & 7) + 1));  // global colour table
  while (need(1)) {
    const unsigned char introducer = b[at++];
    if (introducer == 0x3B) {
      g.valid = at == b.size();
      return g;
    }
    if (introducer == 0x21) {  // extension: label, then sub-blocks
      if (!need(1)) return g;
      if (b[at++] == 0xF9) ++g.graphic_controls;
      if (!skip_sub_blocks()) return g;
    } else if (introducer == 0x2C) {  // image: descriptor, local colour table, LZW data
      if (!need(9)) return g;
      const unsigned char image_flags = b[at + 8];
      at += 9;
      if (image_flags & 0x80) at += 3u * (1u << ((image_flags & 7) + 1));
      if (!need(1)) return g;
      ++at;  // LZW minimum code size
      if (!skip_sub_blocks()) return g;
      ++g.images;
    } else {
      return g;
    }
  }
  return g;
}

// ffprobe's view of a video's first stream: "key=value" lines.
std::string probe(const std::string& path) {
  return run_shell(
             "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
             "stream=codec_name,width,height,pix_fmt,nb_read_frames -of default=nw=1 " +
             path)
      .out;
}

std::vector<std::vector<double>> csv_rows(const std::string& text, std::string& header) {
  std::istringstream in(text);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// The states at every `every`-th point of the grid of dt: for frames on the grid, the
// integrator's own states there, by its plain grid observer (no dense output).
std::vector<std::vector<double>> grid_states(const npend::chain& c, const std::vector<double>& x0,
                                             double t_end, double dt, std::size_t every) {
  npend::integration_options o;
  o.t_end = t_end;
  o.dt = dt;
  std::vector<std::vector<double>> states;
  std::size_t index = 0;
  npend::integrate(c, x0, o, [&](double, std::span<const double> x) {
    if (index++ % every == 0) states.emplace_back(x.begin(), x.end());
  });
  return states;
}

// Frame `k` of a video as rows of RGB pixels, decoded by ffmpeg.
std::string decoded_frame(const std::string& path, int k) {
  return run_shell("ffmpeg -v error -i " + path + " -vf 'select=eq(n\\," + std::to_string(k) +
                   ")' -frames:v 1 -f rawvideo -pix_fmt rgb24 -")
      .out;
}

// The centre of the pixels of the last bob's red (#d62728), and how many there are.
struct blob {
  double x = 0, y = 0;
  int pixels = 0;
};

blob red_pixels(const std::string& rgb, int width) {
  blob b;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    const auto r = static_cast<unsigned char>(rgb[i]), g = static_cast<unsigned char>(rgb[i + 1]),
               bl = static_cast<unsigned char>(rgb[i + 2]);
    if (std::abs(r - 0xd6) > 24 || std::abs(g - 0x27) > 24 || std::abs(bl - 0x28) > 24) continue;
    const auto p = static_cast<int>(i / 3);
    b.x += p % width;
    b.y += p / width;
    ++b.pixels;
  }
  if (b.pixels > 0) {
    b.x /= b.pixels;
    b.y /= b.pixels;
  }
  return b;
}

}  // namespace

TEST_CASE("npend animate: a GIF of t-end * fps + 1 frames at the size asked for") {
  const std::string dir = npend::test::temporary_directory("animate-gif");
  const auto r = run_npend(
      "animate --links 3 --phi 1.5,1.5,1.5 --t-end 1 --fps 20 --size 160x120 "
      "--out " +
      dir + "/a.gif");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("21 frames at 20 fps, 160x120 px") != std::string::npos);
  const gif_summary g = parse_gif(read_bytes(dir + "/a.gif"));
  CHECK(g.valid);
  CHECK(g.width == 160);
  CHECK(g.height == 120);
  CHECK(g.images == 21);
  CHECK(g.graphic_controls == 21);
  // ffprobe agrees, and the temporary file is gone.
  CHECK(probe(dir + "/a.gif").find("nb_read_frames=21") != std::string::npos);
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"a.gif"});
}

TEST_CASE("npend animate: an H.264 MP4 in yuv420p with one frame per 1/fps") {
  const std::string dir = npend::test::temporary_directory("animate-mp4");
  const auto r = run_npend("animate --links 2 --phi 2,1 --t-end 1 --fps 10 --size 160x120 --out " +
                           dir + "/a.mp4");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto bytes = read_bytes(dir + "/a.mp4");
  REQUIRE(bytes.size() > 12);
  CHECK(std::string(bytes.begin() + 4, bytes.begin() + 8) == "ftyp");
  const std::string p = probe(dir + "/a.mp4");
  INFO(p);
  CHECK(p.find("codec_name=h264") != std::string::npos);
  CHECK(p.find("width=160") != std::string::npos);
  CHECK(p.find("height=120") != std::string::npos);
  CHECK(p.find("pix_fmt=yuv420p") != std::string::npos);
  CHECK(p.find("nb_read_frames=11") != std::string::npos);
  // Neither the temporary file nor the frames' folder is left.
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"a.mp4"});
}

TEST_CASE("npend animate: the frames drawn are the integrator's states at t_k = k/fps") {
  const std::string dir = npend::test::temporary_directory("animate-frames");
  const auto r = run_npend(
      "animate --links 3 --phi 1.5,-0.7,2 --p 0.3,0,-0.2 --t-end 1.5 "
      "--fps 20 --size 64x64 --out " +
      dir + "/a.gif --frames-csv " + dir + "/frames.csv");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  std::string header;
  const auto rows = csv_rows(npend::test::read_text(dir + "/frames.csv"), header);
  CHECK(header == "t,H,x_0,y_0,x_1,y_1,x_2,y_2,x_3,y_3");
  REQUIRE(rows.size() == 31);
  // At 20 fps every frame lies on the 1 ms grid (every 50th point): compare with the
  // integrator's grid states there, integrated here on their own.
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{1.5, -0.7, 2, 0.3, 0, -0.2};
  const auto states = grid_states(c, x0, 1.5, 1e-3, 50);
  REQUIRE(states.size() == rows.size());
  std::vector<double> xy(6);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    CAPTURE(k);
    const auto& row = rows[k];
    REQUIRE(row.size() == 10);
    CHECK(row[0] == doctest::Approx(static_cast<double>(k) / 20).epsilon(1e-15));
    CHECK(row[1] == doctest::Approx(c.hamiltonian(states[k])).epsilon(1e-12));
    CHECK(row[2] == 0.0);  // the fixed pivot
    CHECK(row[3] == 0.0);
    c.positions(std::span(states[k]).first(3), xy);
    for (std::size_t i = 0; i < 6; ++i) CHECK(std::fabs(row[4 + i] - xy[i]) < 1e-10);
  }
}

TEST_CASE("npend animate: a driven chain of rods, its pivot drawn where the drive has moved it") {
  const std::string dir = npend::test::temporary_directory("animate-driven");
  const auto r = run_npend(
      "animate --links 2 --rods --pivot vertical:0.2:10 --phi 1,0.5 "
      "--t-end 1 --fps 25 --size 96x96 --out " +
      dir + "/a.gif --frames-csv " + dir + "/frames.csv");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  std::string header;
  const auto rows = csv_rows(npend::test::read_text(dir + "/frames.csv"), header);
  REQUIRE(rows.size() == 26);
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.make_uniform_rods();
  p.pivot = npend::pivot_motion::vertical(0.2, 10);
  const npend::chain c(p);
  const auto states = grid_states(c, {1, 0.5, 0, 0}, 1, 1e-3, 40);
  REQUIRE(states.size() == rows.size());
  std::vector<double> xy(4);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    CAPTURE(k);
    const auto& row = rows[k];
    const double t = row[0];
    // The pivot: r₀ = (0, −a cos Ωt), y down.
    CHECK(row[2] == 0.0);
    CHECK(row[3] == doctest::Approx(-0.2 * std::cos(10 * t)).epsilon(1e-14));
    c.positions(std::span(states[k]).first(2), xy);
    for (std::size_t i = 0; i < 4; ++i)
      CHECK(std::fabs(row[4 + i] - (row[2 + i % 2] + xy[i])) < 1e-10);
  }
  CHECK(parse_gif(read_bytes(dir + "/a.gif")).images == 26);
}

TEST_CASE("npend animate: the standing chain held by --controller lqr, as npend simulate runs it") {
  const std::string dir = npend::test::temporary_directory("animate-lqr");
  const std::string start = "--links 3 --controller lqr --at pi --phi 3.04,3.04,3.04 --t-end 4 ";
  const auto r = run_npend("animate " + start + "--fps 5 --size 64x64 --out " + dir +
                           "/a.gif --frames-csv " + dir + "/frames.csv");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  std::string header;
  const auto rows = csv_rows(npend::test::read_text(dir + "/frames.csv"), header);
  REQUIRE(rows.size() == 21);
  // Every 200th row of npend simulate's trajectory (1 ms grid) is a frame at 5 fps.
  const auto sim = run_npend("simulate " + start);
  REQUIRE(sim.exit_code == 0);
  std::string sim_header;
  const auto trajectory = csv_rows(sim.out, sim_header);
  REQUIRE(trajectory.size() == 4001);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    CAPTURE(k);
    const auto& frame = rows[k];
    const auto& row = trajectory[200 * k];
    // simulate's columns: t, phi_1..3, p_1..3, H, x_1, y_1, ..
    CHECK(frame[0] == doctest::Approx(row[0]).epsilon(1e-12));
    for (std::size_t i = 0; i < 6; ++i) CHECK(std::fabs(frame[4 + i] - row[8 + i]) < 1e-10);
  }
  // Held upright: the last bob 3 m above the pivot (y points down).
  CHECK(rows.back()[9] == doctest::Approx(-3).epsilon(1e-4));
}

TEST_CASE("npend animate: the last bob is drawn at its position, on fixed axes with equal scales") {
  const std::string dir = npend::test::temporary_directory("animate-pixels");
  // No trail, so the red of the last bob is nowhere else. A wide image: the view is
  // widened along x so that a metre spans the same pixels on both axes.
  const int width = 300, height = 200;
  const auto r = run_npend(
      "animate --links 3 --phi 2,-1,0.5 --t-end 0.5 --fps 10 --trail 0 "
      "--size 300x200 --out " +
      dir + "/a.gif");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const npend::chain c(npend::chain_parameters::uniform(3));
  const auto states = grid_states(c, {2, -1, 0.5, 0, 0, 0}, 0.5, 1e-3, 100);
  REQUIRE(states.size() == 6);
  // The view: the chain's reach 3 m plus 8 %, the same scale on both axes.
  const double half_height = 3 * 1.08, half_width = half_height * width / height;
  std::vector<double> xy(6);
  for (const int k : {0, 3, 5}) {
    CAPTURE(k);
    const std::string rgb = decoded_frame(dir + "/a.gif", k);
    REQUIRE(rgb.size() == static_cast<std::size_t>(3 * width * height));
    c.positions(std::span(states[static_cast<std::size_t>(k)]).first(3), xy);
    const double px = (xy[4] + half_width) / (2 * half_width) * width;
    const double py = (xy[5] + half_height) / (2 * half_height) * height;  // y down both
    const blob b = red_pixels(rgb, width);
    CAPTURE(px);
    CAPTURE(py);
    CAPTURE(b.x);
    CAPTURE(b.y);
    CHECK(b.pixels >= 9);  // a dot, not a stray pixel
    CHECK(b.pixels <= 200);
    CHECK(std::hypot(b.x - px, b.y - py) < 2.5);
  }
}

TEST_CASE("npend animate: bad input exits with 2 and leaves no file") {
  const std::string dir = npend::test::temporary_directory("animate-errors");
  const std::string run = "animate --links 2 --phi 1,1 ";
  const struct {
    std::string args, message;
  } cases[] = {
      {"--t-end 1 --out " + dir + "/a.avi",
       "--out: '" + dir + "/a.avi' must be a file name ending in .gif or .mp4"},
      {"--t-end 1 --fps 0 --out " + dir + "/a.gif", "--fps: must be a positive number, got 0"},
      {"--t-end 1 --fps -5 --out " + dir + "/a.mp4", "--fps: must be a positive number, got -5"},
      {"--t-end 1 --fps 60 --out " + dir + "/a.gif", "--fps: a GIF's frame delay"},
      {"--t-end 1 --size 640 --out " + dir + "/a.gif", "--size: '640' is not WIDTHxHEIGHT"},
      {"--t-end 1 --size 0x480 --out " + dir + "/a.gif", "--size: '0x480' is not WIDTHxHEIGHT"},
      {"--t-end 1 --size 321x240 --out " + dir + "/a.mp4",
       "--size: an MP4 (yuv420p) needs an even width and height, got 321x240"},
      {"--t-end 0 --out " + dir + "/a.gif", "--t-end: must be positive, got 0"},
      {"--t-end 1 --trail -1 --out " + dir + "/a.gif", "--trail: must be a number of seconds >= 0"},
      {"--t-end 1 --out " + dir + "/missing/a.gif", "--out: cannot create a file in"},
  };
  for (const auto& k : cases) {
    CAPTURE(k.args);
    const auto r = run_npend(run + k.args);
    CHECK(npend::test::is_input_error(r, k.message));
    CHECK(r.out.empty());
  }
  CHECK(npend::test::directory_listing(dir).empty());
}

TEST_CASE("npend animate: a missing gnuplot or ffmpeg is named, with exit status 1 and no file") {
  const std::string dir = npend::test::temporary_directory("animate-no-tools");
  // A PATH without the tools (the binary is called by its full path).
  const auto r = run_shell("PATH=" + dir + " " + std::string(NPEND_CLI_PATH) +
                           " animate --links 2 --phi 1,1 --t-end 1 --out " + dir + "/a.gif");
  CHECK(r.exit_code == 1);
  CHECK(r.err ==
        "npend animate: error: gnuplot is not installed: it draws the frames (Debian: apt-get "
        "install gnuplot-nox)\n");
  CHECK(npend::test::directory_listing(dir).empty());
}

TEST_CASE("npend animate: SIGINT while drawing leaves neither the file nor the frames' folder") {
  const std::string dir = npend::test::temporary_directory("animate-sigint");
  const auto r =
      run_shell("timeout --preserve-status -s INT 2 " + std::string(NPEND_CLI_PATH) +
                " animate --links 3 --energy 20 --t-end 600 --fps 30 --out " + dir + "/a.mp4");
  INFO(r.err);
  CHECK(r.exit_code == 130);
  CHECK(r.err == "npend animate: interrupted; nothing written to " + dir + "/a.mp4\n");
  CHECK(npend::test::directory_listing(dir).empty());
}

TEST_CASE("npend animate: a progress bar on a terminal while the frames are drawn") {
  const std::string dir = npend::test::temporary_directory("animate-progress");
  // Integrating 60 s takes a fraction of a second; the bar must then follow the drawing. The
  // interrupt comes after 6 s so that a loaded machine still reaches the drawing.
  const std::string run = "timeout --preserve-status -s INT 6 " + std::string(NPEND_CLI_PATH) +
                          " animate --links 3 --phi 1.5,1.5,1.5 --t-end 60 --out " + dir + "/a.mp4";
  // `script` runs the command on a pseudo-terminal and copies what it shows to stdout.
  const auto on_terminal = run_shell("script -qec '" + run + "' /dev/null");
  INFO(on_terminal.out);
  CHECK(on_terminal.out.find("% ") != std::string::npos);
  CHECK(on_terminal.out.find("s left") != std::string::npos);
  CHECK(npend::test::directory_listing(dir).empty());
}

TEST_CASE("npend animate: --help describes every option") {
  const auto r = run_npend("animate --help");
  CHECK(r.exit_code == 0);
  for (const char* option : {"--out", "--fps", "--trail", "--size", "--frames-csv", "--t-end",
                             "--stepper", "--rods", "--pivot", "--phi", "--energy"})
    CHECK_MESSAGE(r.out.find(option) != std::string::npos, option);
}
