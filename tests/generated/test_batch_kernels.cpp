// The generated batch kernels (batch_<n>.cpp) against the scalar generated rhs: each lane
// computes what chain_<n>::rhs computes, apart from the roundings of SLEEF's sines and
// cosines, and a lane's result does not depend on its slot or on the other lanes.
#include <doctest/doctest.h>

#include <algorithm>
#include <batch_index.hpp>
#include <chain_index.hpp>
#include <cmath>
#include <random>
#include <vector>

namespace {

constexpr int lanes = npend::batch_width;

struct problem {
  int n;
  std::vector<double> params;  // [m, l, g]
  std::vector<double> states;  // count states of 2n, one after the other (AoS)
};

problem random_problem(int n, int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mass(0.2, 5), length(0.2, 3), angle(-7, 7),
      momentum(-20, 20);
  problem p{n, {}, {}};
  for (int i = 0; i < n; ++i) p.params.push_back(mass(rng));
  for (int i = 0; i < n; ++i) p.params.push_back(length(rng));
  p.params.push_back(9.81);
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < n; ++i) p.states.push_back(angle(rng));
    for (int i = 0; i < n; ++i) p.states.push_back(momentum(rng));
  }
  return p;
}

// Batch rhs of lanes states (AoS in, AoS out), through SoA.
std::vector<double> batch_rhs(const npend::batch_kernels& k, int n, const double* states,
                              const double* params) {
  const int m = 2 * n;
  std::vector<double> x(static_cast<std::size_t>(m * lanes)), dx(x.size()), out(x.size());
  for (int l = 0; l < lanes; ++l)
    for (int i = 0; i < m; ++i) x[static_cast<std::size_t>(i * lanes + l)] = states[l * m + i];
  k.rhs_batch(x.data(), params, dx.data(), 1, 0);
  for (int l = 0; l < lanes; ++l)
    for (int i = 0; i < m; ++i)
      out[static_cast<std::size_t>(l * m + i)] = dx[static_cast<std::size_t>(i * lanes + l)];
  return out;
}

bool sines_agree(const double* x, int n) {
  double s[lanes], c[lanes], a[lanes];
  for (int i = 0; i < n; ++i) {
    std::fill(a, a + lanes, x[i]);
    npend::batch_sincos(a, s, c);
    if (s[0] != std::sin(x[i]) || c[0] != std::cos(x[i])) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("rhs_batch: agrees with the scalar rhs for 1 to 6 links on random states") {
  std::mt19937_64 rng(20261125);
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    const npend::chain_kernels* scalar = npend::generated::find_chain(n);
    const npend::batch_kernels* batch = npend::generated::find_batch(n);
    REQUIRE(scalar != nullptr);
    REQUIRE(batch != nullptr);
    REQUIRE(batch->links == n);
    REQUIRE(batch->width == lanes);
    const int m = 2 * n;
    const int groups = 500;
    const problem p = random_problem(n, groups * lanes, rng);
    double worst = 0;
    int identical = 0, compared = 0, with_equal_sines = 0;
    for (int gi = 0; gi < groups; ++gi) {
      const double* states = p.states.data() + gi * lanes * m;
      const auto got = batch_rhs(*batch, n, states, p.params.data());
      for (int l = 0; l < lanes; ++l) {
        std::vector<double> want(static_cast<std::size_t>(m));
        scalar->rhs(states + l * m, p.params.data(), want.data());
        // Relative to the largest term of each half (rates, then forces).
        double scale_rates = 0, scale_forces = 0;
        for (int i = 0; i < n; ++i) {
          scale_rates = std::max(scale_rates, std::fabs(want[static_cast<std::size_t>(i)]));
          scale_forces = std::max(scale_forces, std::fabs(want[static_cast<std::size_t>(n + i)]));
        }
        bool same = true;
        for (int i = 0; i < m; ++i) {
          const double w = want[static_cast<std::size_t>(i)];
          const double g = got[static_cast<std::size_t>(l * m + i)];
          const double scale = i < n ? scale_rates : scale_forces;
          const double rel = std::fabs(g - w) / scale;
          worst = std::max(worst, rel);
          same = same && g == w;
        }
        ++compared;
        identical += same;
        // Where SLEEF's sines and cosines equal std::sin's, the arithmetic is the scalar
        // kernel's: no reordering, so the same bits (without FMA contraction, which the
        // compiler may apply differently to scalar and vector code).
#ifndef __FMA__
        if (sines_agree(states + l * m, n)) {
          ++with_equal_sines;
          CHECK(same);
        }
#endif
      }
    }
    MESSAGE("n = " << n << ": worst relative difference " << worst << ", " << identical << " of "
                   << compared << " states bit-identical, " << with_equal_sines
                   << " with equal sines");
    CHECK(worst <= 1e-14);
  }
}

TEST_CASE("rhs_batch: a lane's result does not depend on its slot or on the other lanes") {
  std::mt19937_64 rng(7);
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    const npend::batch_kernels& batch = *npend::generated::find_batch(n);
    const int m = 2 * n;
    const problem p = random_problem(n, 2 * lanes, rng);
    const double* probe = p.states.data();  // state 0
    // The probe in every lane at once: all lanes the same bits.
    std::vector<double> same_everywhere;
    for (int l = 0; l < lanes; ++l) same_everywhere.insert(same_everywhere.end(), probe, probe + m);
    const auto all = batch_rhs(batch, n, same_everywhere.data(), p.params.data());
    for (int l = 1; l < lanes; ++l)
      for (int i = 0; i < m; ++i)
        CHECK(all[static_cast<std::size_t>(l * m + i)] == all[static_cast<std::size_t>(i)]);
    // The probe in slot `slot` among other random states: the bits of lane 0 above.
    for (int slot = 0; slot < lanes; ++slot) {
      std::vector<double> mixed(p.states.begin() + lanes * m, p.states.end());
      std::copy(probe, probe + m, mixed.begin() + slot * m);
      const auto got = batch_rhs(batch, n, mixed.data(), p.params.data());
      for (int i = 0; i < m; ++i)
        CHECK(got[static_cast<std::size_t>(slot * m + i)] == all[static_cast<std::size_t>(i)]);
    }
  }
}

TEST_CASE("tangent_batch: f as rhs_batch, and J w as the scalar Jacobian times w, 1 to 6 links") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> direction(-1, 1);
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    const npend::chain_kernels& scalar = *npend::generated::find_chain(n);
    const npend::batch_kernels& batch = *npend::generated::find_batch(n);
    REQUIRE(static_cast<bool>(batch.tangent_batch));
    const int m = 2 * n;
    const auto mu = static_cast<std::size_t>(m);
    const problem p = random_problem(n, 200 * lanes, rng);
    double worst_f = 0, worst_jw = 0;
    for (int gi = 0; gi < 200; ++gi) {
      const double* states = p.states.data() + gi * lanes * m;
      std::vector<double> x(mu * lanes), w(x.size()), dx(x.size()), dw(x.size());
      for (int l = 0; l < lanes; ++l)
        for (int i = 0; i < m; ++i) {
          x[static_cast<std::size_t>(i * lanes + l)] = states[l * m + i];
          w[static_cast<std::size_t>(i * lanes + l)] = direction(rng);
        }
      batch.tangent_batch(x.data(), w.data(), p.params.data(), dx.data(), dw.data(), 1, 0);
      std::vector<double> f_batch(x.size());
      batch.rhs_batch(x.data(), p.params.data(), f_batch.data(), 1, 0);
      for (int l = 0; l < lanes; ++l) {
        std::vector<double> jac(mu * mu), lane_w(mu);
        scalar.jacobian(states + l * m, p.params.data(), jac.data());
        for (int i = 0; i < m; ++i)
          lane_w[static_cast<std::size_t>(i)] = w[static_cast<std::size_t>(i * lanes + l)];
        // |J| |w| row by row: the size of the terms J w sums, for a relative error.
        for (int i = 0; i < m; ++i) {
          double want = 0, scale = 0;
          for (int j = 0; j < m; ++j) {
            const double term =
                jac[static_cast<std::size_t>(i * m + j)] * lane_w[static_cast<std::size_t>(j)];
            want += term;
            scale += std::fabs(term);
          }
          const auto at = static_cast<std::size_t>(i * lanes + l);
          if (scale > 0) worst_jw = std::max(worst_jw, std::fabs(dw[at] - want) / scale);
          worst_f = std::max(
              worst_f, std::fabs(dx[at] - f_batch[at]) / std::max(1.0, std::fabs(f_batch[at])));
        }
      }
    }
    MESSAGE("n = " << n << ": J w worst relative difference " << worst_jw << ", f " << worst_f);
    CHECK(worst_jw <= 1e-12);
    CHECK(worst_f <= 1e-14);
  }
}

TEST_CASE("tangents_batch: k vectors at once, each bit for bit tangent_batch's, 1 to 6 links") {
  // The same program split in two (what the vectors share once, each vector's statements in
  // their own loop): no operation changes, so neither may a bit.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> direction(-1, 1);
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    const npend::batch_kernels& batch = *npend::generated::find_batch(n);
    REQUIRE(static_cast<bool>(batch.tangents_batch));
    const auto block = static_cast<std::size_t>(2 * n * lanes);
    const problem p = random_problem(n, 50 * lanes, rng);
    long compared = 0, differing = 0;
    for (int gi = 0; gi < 50; ++gi) {
      const int count = 1 + gi % (2 * n);  // 1 .. 2n vectors, as GALI_k takes
      std::vector<double> x(block), ws(block * static_cast<std::size_t>(count)), dws(ws.size()),
          dx(block), dx_one(block), dw_one(block);
      for (int l = 0; l < lanes; ++l)
        for (int i = 0; i < 2 * n; ++i)
          x[static_cast<std::size_t>(i * lanes + l)] =
              p.states[static_cast<std::size_t>((gi * lanes + l) * 2 * n + i)];
      for (double& v : ws) v = direction(rng);
      batch.tangents_batch(x.data(), ws.data(), count, p.params.data(), dx.data(), dws.data(), 1,
                           0);
      for (int j = 0; j < count; ++j) {
        const std::size_t offset = block * static_cast<std::size_t>(j);
        batch.tangent_batch(x.data(), ws.data() + offset, p.params.data(), dx_one.data(),
                            dw_one.data(), 1, 0);
        for (std::size_t i = 0; i < block; ++i) {
          ++compared;
          differing += dws[offset + i] == dw_one[i] ? 0 : 1;
          if (j == 0) differing += dx[i] == dx_one[i] ? 0 : 1;
        }
      }
    }
    MESSAGE("n = " << n << ": " << compared << " tangent coordinates compared");
    CHECK(differing == 0);
  }
}

TEST_CASE(
    "batch kernels: several blocks at a stride in one call, each the bits of the block alone") {
  // One call for all the blocks computes what depends on the parameters once; each block's
  // arithmetic must stay that of a call on it alone, and the gaps between blocks untouched.
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> direction(-1, 1);
  constexpr int blocks = 3, count = 2;
  for (int n = 1; n <= 6; ++n) {
    CAPTURE(n);
    const npend::batch_kernels& batch = *npend::generated::find_batch(n);
    const auto block = static_cast<std::size_t>(2 * n * lanes);
    // Per block: x, then `count` tangent vectors, then a gap of one lane's width.
    const std::size_t stride = block * (1 + count) + lanes;
    const problem p = random_problem(n, blocks * lanes, rng);
    std::vector<double> in(stride * blocks);
    for (double& v : in) v = direction(rng);
    for (int b = 0; b < blocks; ++b)
      for (int l = 0; l < lanes; ++l)
        for (int i = 0; i < 2 * n; ++i)
          in[stride * static_cast<std::size_t>(b) + static_cast<std::size_t>(i * lanes + l)] =
              p.states[static_cast<std::size_t>((b * lanes + l) * 2 * n + i)];
    constexpr double untouched = -12345.0;
    std::vector<double> all(in.size(), untouched), one(in.size(), untouched);
    long differing = 0, gaps_written = 0;
    const auto compare = [&] {
      for (std::size_t i = 0; i < in.size(); ++i) differing += all[i] == one[i] ? 0 : 1;
      for (int b = 0; b < blocks; ++b)
        for (std::size_t i = stride - lanes; i < stride; ++i)
          gaps_written += all[stride * static_cast<std::size_t>(b) + i] == untouched ? 0 : 1;
    };
    const double* params = p.params.data();
    batch.rhs_batch(in.data(), params, all.data(), blocks, stride);
    for (int b = 0; b < blocks; ++b) {
      const std::size_t o = stride * static_cast<std::size_t>(b);
      batch.rhs_batch(in.data() + o, params, one.data() + o, 1, 0);
    }
    compare();
    batch.tangent_batch(in.data(), in.data() + block, params, all.data(), all.data() + block,
                        blocks, stride);
    for (int b = 0; b < blocks; ++b) {
      const std::size_t o = stride * static_cast<std::size_t>(b);
      batch.tangent_batch(in.data() + o, in.data() + o + block, params, one.data() + o,
                          one.data() + o + block, 1, 0);
    }
    compare();
    batch.tangents_batch(in.data(), in.data() + block, count, params, all.data(),
                         all.data() + block, blocks, stride);
    for (int b = 0; b < blocks; ++b) {
      const std::size_t o = stride * static_cast<std::size_t>(b);
      batch.tangents_batch(in.data() + o, in.data() + o + block, count, params, one.data() + o,
                           one.data() + o + block, 1, 0);
    }
    compare();
    CHECK(differing == 0);
    CHECK(gaps_written == 0);
  }
}
