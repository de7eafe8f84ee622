#include "npend/analysis/series/series_lyapunov.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <utility>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/nearest_neighbours.hpp"
#include "npend/analysis/series/delay_embedding.hpp"

namespace npend {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// nanoflann's dataset concept over the first `count` rows of the delay vectors.
struct delay_rows {
  const double* points;
  std::size_t dimension;
  std::size_t count;

  std::size_t kdtree_get_point_count() const { return count; }
  double kdtree_get_pt(std::uint32_t row, std::size_t coordinate) const {
    return points[row * dimension + coordinate];
  }
  template <class box>
  bool kdtree_get_bbox(box&) const {
    return false;
  }
};

using tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, delay_rows>,
                                                 delay_rows, -1, std::uint32_t>;

// A nanoflann result set keeping every row within a squared radius outside the query's
// Theiler window, at a nonzero distance.
class admissible_within {
 public:
  admissible_within(double radius_squared, std::size_t query, std::size_t window,
                    std::vector<std::pair<double, std::uint32_t>>& found)
      : m_radius_squared(radius_squared), m_query(query), m_window(window), m_found(found) {
    m_found.clear();
  }
  double worstDist() const { return m_radius_squared; }
  bool full() const { return true; }
  bool addPoint(double distance_squared, std::uint32_t row) {
    const std::size_t gap = row > m_query ? row - m_query : m_query - row;
    if (gap > m_window && distance_squared > 0 && distance_squared < m_radius_squared)
      m_found.emplace_back(distance_squared, row);
    return true;
  }

 private:
  double m_radius_squared;
  std::size_t m_query, m_window;
  std::vector<std::pair<double, std::uint32_t>>& m_found;
};

double distance(const delay_vectors& v, std::size_t a, std::size_t b) {
  double sum = 0;
  for (std::size_t c = 0; c < v.dimension; ++c) {
    const double d = v.points[a * v.dimension + c] - v.points[b * v.dimension + c];
    sum += d * d;
  }
  return std::sqrt(sum);
}

void validate(const stretching_options& o) {
  if (o.delay < 1) throw std::invalid_argument("stretching: delay must be at least 1 sample");
  if (o.dimension < 1) throw std::invalid_argument("stretching: dimension must be at least 1");
  if (o.horizon < 1) throw std::invalid_argument("stretching: horizon must be at least 1 sample");
  if (o.step < 1) throw std::invalid_argument("stretching: step must be at least 1 sample");
  if (o.max_neighbours < 1)
    throw std::invalid_argument("stretching: max_neighbours must be at least 1");
  if (o.groups < 2) throw std::invalid_argument("stretching: groups must be at least 2");
  for (double r : o.radii)
    if (!(r > 0) || !std::isfinite(r))
      throw std::invalid_argument(
          fmt::format("stretching: radius {} is not positive and finite", r));
}

// Least-squares line through (t, s) for t in [from, to] and finite s: slope, intercept,
// standard error of the slope; nullopt for fewer than `minimum` points.
struct line {
  double slope, intercept, standard_error;
};
std::optional<line> fit_line(const std::vector<double>& t, const std::vector<double>& s,
                             double from, double to, std::size_t minimum = 3) {
  const double slack = 1e-9 * std::max(1.0, std::fabs(to));
  double st = 0, ss = 0;
  std::size_t n = 0;
  for (std::size_t j = 0; j < t.size(); ++j)
    if (t[j] >= from - slack && t[j] <= to + slack && std::isfinite(s[j])) {
      st += t[j];
      ss += s[j];
      ++n;
    }
  if (n < minimum || n < 2) return std::nullopt;
  const double mt = st / static_cast<double>(n), ms = ss / static_cast<double>(n);
  double stt = 0, sts = 0;
  for (std::size_t j = 0; j < t.size(); ++j)
    if (t[j] >= from - slack && t[j] <= to + slack && std::isfinite(s[j])) {
      stt += (t[j] - mt) * (t[j] - mt);
      sts += (t[j] - mt) * (s[j] - ms);
    }
  if (!(stt > 0)) return std::nullopt;
  line l{sts / stt, 0, nan};
  l.intercept = ms - l.slope * mt;
  if (n > 2) {
    double residuals = 0;
    for (std::size_t j = 0; j < t.size(); ++j)
      if (t[j] >= from - slack && t[j] <= to + slack && std::isfinite(s[j])) {
        const double r = s[j] - (l.intercept + l.slope * t[j]);
        residuals += r * r;
      }
    l.standard_error = std::sqrt(residuals / static_cast<double>(n - 2) / stt);
  }
  return l;
}

double median(std::vector<double> v) {
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// The series' checks: finite, varying, long enough for the embedding and the horizon.
void check_series(std::span<const double> x, const std::string& name, const stretching_options& o) {
  detail::require_finite_series(x, name.c_str(), 4);
  detail::require_varying(x, name.c_str(), "it has no neighbours to follow");
  const std::size_t span = (o.dimension - 1) * o.delay;
  if (x.size() <= span + o.horizon)
    throw std::invalid_argument(fmt::format(
        "{} has {} samples; dimension {} at delay {} with a horizon of {} needs more than {}", name,
        x.size(), o.dimension, o.delay, o.horizon, span + o.horizon));
}

// The stretching curves over given delay vectors (rows in time order, one per sample time).
stretching_result stretching_of(const delay_vectors& v, const stretching_options& o);

}  // namespace

stretching_result stretching_curves(std::span<const double> x, const stretching_options& o) {
  validate(o);
  check_series(x, "x", o);
  return stretching_of(delay_embedding(x, o.delay, o.dimension), o);
}

stretching_result stretching_curves(std::span<const std::vector<double>> series,
                                    const stretching_options& o) {
  validate(o);
  if (series.empty()) throw std::invalid_argument("stretching: no series given");
  for (std::size_t c = 0; c < series.size(); ++c) {
    if (series[c].size() != series[0].size())
      throw std::invalid_argument(fmt::format(
          "stretching: series {} has {} samples, series 1 has {}: they must be sampled together",
          c + 1, series[c].size(), series[0].size()));
    check_series(series[c], fmt::format("series {}", c + 1), o);
  }
  // Row i of the joint embedding: the m delay coordinates of each series in turn.
  std::vector<delay_vectors> each;
  for (const auto& x : series) each.push_back(delay_embedding(x, o.delay, o.dimension));
  delay_vectors joint;
  joint.dimension = o.dimension * series.size();
  joint.delay = o.delay;
  joint.count = each.front().count;
  joint.points.reserve(joint.count * joint.dimension);
  for (std::size_t i = 0; i < joint.count; ++i)
    for (const auto& v : each)
      joint.points.insert(joint.points.end(),
                          v.points.begin() + static_cast<std::ptrdiff_t>(i * v.dimension),
                          v.points.begin() + static_cast<std::ptrdiff_t>((i + 1) * v.dimension));
  return stretching_of(joint, o);
}

std::vector<std::vector<double>> standardised_series(std::span<const std::vector<double>> series) {
  std::vector<std::vector<double>> out;
  for (std::size_t c = 0; c < series.size(); ++c) {
    const std::string name = fmt::format("series {}", c + 1);
    detail::require_finite_series(series[c], name.c_str(), 2);
    detail::require_varying(series[c], name.c_str(), "it cannot be standardised");
    double mean = 0;
    for (double v : series[c]) mean += v;
    mean /= static_cast<double>(series[c].size());
    double squares = 0;
    for (double v : series[c]) squares += (v - mean) * (v - mean);
    const double deviation = std::sqrt(squares / static_cast<double>(series[c].size()));
    std::vector<double> scaled;
    scaled.reserve(series[c].size());
    for (double v : series[c]) scaled.push_back((v - mean) / deviation);
    out.push_back(std::move(scaled));
  }
  return out;
}

namespace {

stretching_result stretching_of(const delay_vectors& v, const stretching_options& o) {
  stretching_result r;
  r.vectors = v.count - o.horizon;
  const std::size_t usable = r.vectors;
  if (usable < 2 * o.theiler_window + 3 || usable < 2 * o.groups)
    throw std::invalid_argument(fmt::format(
        "x is too short: {} delay vectors have {} samples ahead; at least {} are needed "
        "(2 x Theiler window {} + 3, and 2 per group)",
        usable, o.horizon, std::max(2 * o.theiler_window + 3, 2 * o.groups), o.theiler_window));
  for (std::size_t n = 0; n <= o.horizon; n += o.step) r.steps.push_back(n);

  const std::size_t references =
      o.max_references == 0 ? usable : std::min(usable, o.max_references);
  const auto reference_row = [&](std::size_t k) { return k * usable / references; };

  std::vector<double> radii = o.radii;
  if (radii.empty()) {
    const auto nearest = detail::nearest_neighbours(
        std::span<const double>(v.points.data(), usable * v.dimension), v.dimension, v.dimension,
        o.theiler_window, detail::vector_norm::euclidean, references);
    std::vector<double> distances;
    for (const auto& n : nearest)
      if (n.index != detail::neighbour::none) distances.push_back(n.distance);
    if (distances.empty())
      throw std::invalid_argument("x: no delay vector has a neighbour outside the Theiler window");
    const double typical = median(distances);
    radii = {typical, 2 * typical, 4 * typical};
  }
  std::sort(radii.begin(), radii.end());

  const delay_rows rows{v.points.data(), v.dimension, usable};
  const tree index(static_cast<int>(v.dimension), rows,
                   nanoflann::KDTreeSingleIndexAdaptorParams(10));
  const std::size_t points = r.steps.size();
  // Sums of ln(mean distance) and their counts, per radius, group and step.
  const std::size_t radius_count = radii.size();
  std::vector<double> sums(radius_count * o.groups * points, 0.0);
  std::vector<std::size_t> counts(radius_count * o.groups * points, 0);
  std::vector<std::size_t> with_neighbours(radius_count, 0);
  std::vector<double> neighbour_total(radius_count, 0.0);
  const auto at = [&](std::size_t radius, std::size_t group, std::size_t step) {
    return (radius * o.groups + group) * points + step;
  };

  std::vector<std::pair<double, std::uint32_t>> found;
  std::vector<double> separation(points);
  for (std::size_t k = 0; k < references; ++k) {
    const std::size_t i = reference_row(k);
    const std::size_t group = k * o.groups / references;
    admissible_within within(radii.back() * radii.back(), i, o.theiler_window, found);
    index.findNeighbors(within, v.points.data() + i * v.dimension, nanoflann::SearchParams());
    std::sort(found.begin(), found.end());
    for (std::size_t q = 0; q < radius_count; ++q) {
      std::size_t used = 0;
      while (used < found.size() && used < o.max_neighbours &&
             found[used].first < radii[q] * radii[q])
        ++used;
      if (used == 0) continue;
      ++with_neighbours[q];
      neighbour_total[q] += static_cast<double>(used);
      std::fill(separation.begin(), separation.end(), 0.0);
      for (std::size_t u = 0; u < used; ++u)
        for (std::size_t p = 0; p < points; ++p)
          separation[p] += distance(v, i + r.steps[p], found[u].second + r.steps[p]);
      for (std::size_t p = 0; p < points; ++p)
        if (separation[p] > 0) {
          sums[at(q, group, p)] += std::log(separation[p] / static_cast<double>(used));
          ++counts[at(q, group, p)];
        }
    }
  }

  for (std::size_t q = 0; q < radius_count; ++q) {
    stretching_curve c;
    c.radius = radii[q];
    c.references = with_neighbours[q];
    c.mean_neighbours =
        c.references > 0 ? neighbour_total[q] / static_cast<double>(c.references) : 0.0;
    c.s.assign(points, nan);
    c.group_s.assign(o.groups, std::vector<double>(points, nan));
    for (std::size_t p = 0; p < points; ++p) {
      double total = 0;
      std::size_t count = 0;
      for (std::size_t g = 0; g < o.groups; ++g) {
        const std::size_t n = counts[at(q, g, p)];
        if (n > 0) c.group_s[g][p] = sums[at(q, g, p)] / static_cast<double>(n);
        total += sums[at(q, g, p)];
        count += n;
      }
      if (count > 0) c.s[p] = total / static_cast<double>(count);
    }
    r.curves.push_back(std::move(c));
  }
  return r;
}

// The checks of the fit options, before any curve is computed.
void check_fit_options(double dt, const series_lyapunov_options& o) {
  detail::require_sample_spacing(dt);
  const double horizon = static_cast<double>(o.stretching.horizon) * dt;
  if (o.fit_from.has_value() != o.fit_to.has_value())
    throw std::invalid_argument("series_lyapunov: give both ends of the fit range, or neither");
  if (o.fit_from &&
      !(*o.fit_from >= 0 && *o.fit_from < *o.fit_to && *o.fit_to <= horizon * (1 + 1e-12)))
    throw std::invalid_argument(fmt::format(
        "series_lyapunov: the fit range {} ... {} s must satisfy 0 <= from < to <= the horizon "
        "{} s",
        *o.fit_from, *o.fit_to, horizon));
}

// The middle curve (the mean of the two middle ones for an even count).
std::vector<double> middle_curve(const std::vector<stretching_curve>& curves) {
  const std::size_t m = curves.size() / 2;
  std::vector<double> s = curves[m].s;
  if (curves.size() % 2 == 0)
    for (std::size_t p = 0; p < s.size(); ++p) s[p] = 0.5 * (s[p] + curves[m - 1].s[p]);
  return s;
}

// S of the middle curve at the first finite point at or after time `t` (NaN if none).
double curve_at(const series_lyapunov_result& r, const std::vector<double>& s, double t) {
  for (std::size_t p = 0; p < s.size(); ++p)
    if (static_cast<double>(r.stretching.steps[p]) * r.dt >= t - 1e-9 * r.dt && std::isfinite(s[p]))
      return s[p];
  return nan;
}

// The embedding window max(1, (m − 1)τ) in samples.
std::size_t embedding_window(const series_lyapunov_options& o) {
  return std::max<std::size_t>(1, (o.stretching.dimension - 1) * o.stretching.delay);
}

// Whether the curve saturated before [from, to]: S grew by at least 1 from Δt = 0 to `from`
// and by less than half of that within the range. The growths go to `before` and `within`.
bool saturated_before(const series_lyapunov_result& r, const std::vector<double>& s, double from,
                      double to, double& before, double& within) {
  double start = nan;
  for (double v : s)
    if (std::isfinite(v)) {
      start = v;
      break;
    }
  const double at_from = curve_at(r, s, from);
  before = at_from - start;
  within = curve_at(r, s, to) - at_from;
  return before >= 1 && within < 0.5 * before;
}

// Why a curve that saturated before `range` (starting at `from` s) has no linear region there.
std::string saturation_reason(double before, double from, double within, std::string_view range) {
  return fmt::format(
      "the stretching curve grew by {:.2g} (ln units) before {} ({:.4g} s) and by only {:.2g} "
      "within it: the neighbours separated within the embedding window, as false neighbours of "
      "the embedding do, so its slope is not the maximal exponent (embed more observables, or a "
      "longer series)",
      before, range, from, within);
}

// The automatic fit range on the middle curve (s): from the end of the embedding window to
// half-way up to saturation (series_lyapunov.hpp).
std::pair<double, double> automatic_fit_range(const series_lyapunov_result& r,
                                              const series_lyapunov_options& o) {
  const std::vector<double> s = middle_curve(r.stretching.curves);
  // After the embedding window (m − 1)τ: before it the neighbours' separation still
  // turns into the unstable direction and the delay coordinates mix old and new samples.
  const std::size_t window = embedding_window(o);
  std::size_t first = 0;
  while (first < s.size() && (r.stretching.steps[first] < window || !std::isfinite(s[first])))
    ++first;
  if (first + 2 >= s.size()) first = 0;
  while (first < s.size() && !std::isfinite(s[first])) ++first;
  if (first == s.size())
    throw std::invalid_argument(
        "series_lyapunov: no reference vector has a neighbour within the radii");
  double top = s[first];
  for (std::size_t p = first; p < s.size(); ++p)
    if (std::isfinite(s[p])) top = std::max(top, s[p]);
  const double half = s[first] + 0.5 * (top - s[first]);
  std::size_t from = first, to = s.size() - 1;
  // A curve that rises by less than 1 (a factor e) has no saturation to stop before: all of it.
  for (std::size_t p = first; top - s[first] >= 1 && p < s.size(); ++p)
    if (std::isfinite(s[p]) && s[p] >= half) {
      to = p;
      break;
    }
  // At least three points of the curve.
  while (to < from + 2 && to + 1 < s.size()) ++to;
  while (to < from + 2 && from > 0) --from;
  return {static_cast<double>(r.stretching.steps[from]) * r.dt,
          static_cast<double>(r.stretching.steps[to]) * r.dt};
}

// Whether the fit range is a linear region (series_lyapunov.hpp says when it is not). A
// given range is judged as the automatic one is, and more: the curve must not have saturated
// before the automatic range (then no range of it measures the exponent), and the range must
// not start within the embedding window, where the automatic range never starts.
void judge_linear_region(series_lyapunov_result& r, const series_lyapunov_options& o) {
  const std::vector<double> s = middle_curve(r.stretching.curves);
  const bool saturated =
      saturated_before(r, s, r.fit_from, r.fit_to, r.growth_before_fit, r.growth_in_fit);
  const auto& f = r.fits[r.fits.size() / 2];
  const double half = 0.5 * (r.fit_to - r.fit_from);
  const double bend = std::fabs(f.slope_first_half - f.slope_second_half) * half;
  const double window = static_cast<double>(embedding_window(o)) * r.dt;
  if (saturated) {
    r.linear_region = false;
    r.nonlinearity =
        saturation_reason(r.growth_before_fit, r.fit_from, r.growth_in_fit, "the fit range");
    return;
  }
  if (!r.automatic_range) {
    const auto [from, to] = automatic_fit_range(r, o);
    double before = 0, within = 0;
    if (saturated_before(r, s, from, to, before, within)) {
      r.linear_region = false;
      r.nonlinearity = fmt::format(
          "no range of the curve is linear, the given {:.4g} ... {:.4g} s neither: {}", r.fit_from,
          r.fit_to,
          saturation_reason(before, from, within, "the range chosen after the embedding window"));
      return;
    }
    if (r.fit_from < window * (1 - 1e-9)) {
      r.linear_region = false;
      r.nonlinearity = fmt::format(
          "the fit range starts at {:.4g} s, within the embedding window max(1, m - 1) tau = "
          "{:.4g} s, where the separations still turn into the unstable direction and the "
          "delay coordinates mix old and new samples: the curve bends there (start the fit "
          "range at {:.4g} s or later)",
          r.fit_from, window, window);
      return;
    }
  }
  if (bend > std::max(0.25 * std::fabs(r.growth_in_fit), 0.1)) {
    r.linear_region = false;
    r.nonlinearity = fmt::format(
        "the stretching curve bends in the fit range {:.4g} ... {:.4g} s: its slope is {:.3g} /s "
        "over the first half and {:.3g} /s over the second, so no straight stretch measures the "
        "maximal exponent",
        r.fit_from, r.fit_to, f.slope_first_half, f.slope_second_half);
  }
}

// The rise of the middle radius's curve and the warnings on the estimate
// (series_lyapunov_result::warnings).
void add_warnings(series_lyapunov_result& r) {
  const auto& middle = r.stretching.curves[r.stretching.curves.size() / 2].s;
  double low = INFINITY, high = -INFINITY;
  for (double v : middle)
    if (std::isfinite(v)) {
      low = std::min(low, v);
      high = std::max(high, v);
    }
  r.rise = high - low;
  if (!r.linear_region) r.warnings.push_back("no estimate: " + r.nonlinearity);
  if (r.rise < 3)
    r.warnings.push_back(
        r.linear_region && r.maximal_exponent > 2 * r.uncertainty
            ? fmt::format("the stretching curve rises by only {:.2g} (ln units) over the horizon: "
                          "the estimate rests on few e-foldings of a short linear region (more "
                          "samples give closer neighbours and a longer one)",
                          r.rise)
            : fmt::format(
                  "the stretching curve rises by only {:.2g} (ln units) over the horizon: either "
                  "nearby states do not separate (regular motion, exponent 0) or the neighbours "
                  "are too far apart for a linear region (a series too short for its dimension), "
                  "and then the slope need not be the maximal exponent",
                  r.rise));
  if (r.linear_region && r.uncertainty > 0.25 * std::fabs(r.maximal_exponent) &&
      r.maximal_exponent > 0)
    r.warnings.emplace_back(
        "the uncertainty is more than a quarter of the exponent: the curve has no "
        "clear linear region in the fit range (see --fit)");
}

// The fit of the slope to the curves of `stretching`, and the verdict on its range.
series_lyapunov_result fit_stretching(stretching_result stretching, double dt,
                                      const series_lyapunov_options& o) {
  series_lyapunov_result r;
  r.dt = dt;
  r.stretching = std::move(stretching);
  const auto& curves = r.stretching.curves;
  std::vector<double> t;
  for (std::size_t n : r.stretching.steps) t.push_back(static_cast<double>(n) * dt);

  if (o.fit_from) {
    r.fit_from = *o.fit_from;
    r.fit_to = *o.fit_to;
  } else {
    r.automatic_range = true;
    std::tie(r.fit_from, r.fit_to) = automatic_fit_range(r, o);
  }

  std::vector<double> slopes;
  double statistical = 0, range = 0;
  std::size_t statistical_count = 0;
  for (const auto& c : curves) {
    const auto whole = fit_line(t, c.s, r.fit_from, r.fit_to);
    if (!whole)
      throw std::invalid_argument(fmt::format(
          "series_lyapunov: the fit range {} ... {} s holds fewer than 3 points of the stretching "
          "curve for radius {:.3g}; widen it",
          r.fit_from, r.fit_to, c.radius));
    stretching_fit f;
    f.radius = c.radius;
    f.slope = whole->slope;
    f.intercept = whole->intercept;
    f.standard_error = whole->standard_error;
    const double middle = 0.5 * (r.fit_from + r.fit_to);
    const auto first = fit_line(t, c.s, r.fit_from, middle, 2);
    const auto second = fit_line(t, c.s, middle, r.fit_to, 2);
    f.slope_first_half = first ? first->slope : f.slope;
    f.slope_second_half = second ? second->slope : f.slope;
    for (const auto& g : c.group_s)
      if (const auto l = fit_line(t, g, r.fit_from, r.fit_to)) f.group_slopes.push_back(l->slope);
    f.group_standard_error = nan;
    if (f.group_slopes.size() >= 2) {
      double mean = 0, squares = 0;
      for (double s : f.group_slopes) mean += s;
      mean /= static_cast<double>(f.group_slopes.size());
      for (double s : f.group_slopes) squares += (s - mean) * (s - mean);
      const auto groups = static_cast<double>(f.group_slopes.size());
      f.group_standard_error = std::sqrt(squares / (groups - 1) / groups);
      statistical += f.group_standard_error;
      ++statistical_count;
    }
    range += 0.5 * std::fabs(f.slope_first_half - f.slope_second_half);
    slopes.push_back(f.slope);
    r.fits.push_back(std::move(f));
  }
  double sum = 0;
  for (double s : slopes) sum += s;
  r.maximal_exponent = sum / static_cast<double>(slopes.size());
  const auto [low, high] = std::minmax_element(slopes.begin(), slopes.end());
  r.radius_uncertainty = 0.5 * (*high - *low);
  r.range_uncertainty = range / static_cast<double>(slopes.size());
  r.statistical_uncertainty =
      statistical_count > 0 ? statistical / static_cast<double>(statistical_count) : nan;
  r.uncertainty = std::sqrt((std::isfinite(r.statistical_uncertainty)
                                 ? r.statistical_uncertainty * r.statistical_uncertainty
                                 : 0.0) +
                            r.radius_uncertainty * r.radius_uncertainty +
                            r.range_uncertainty * r.range_uncertainty);
  judge_linear_region(r, o);
  add_warnings(r);
  return r;
}

}  // namespace

std::size_t kantz_dimension(std::size_t series) {
  if (series == 0) throw std::invalid_argument("kantz_dimension: series must be at least 1");
  return series > 1 ? 1 : 6;
}

series_lyapunov_options kantz_options(std::size_t samples, std::size_t series,
                                      const kantz_choices& choices) {
  if (samples == 0) throw std::invalid_argument("kantz_options: samples must be at least 1");
  if (series == 0) throw std::invalid_argument("kantz_options: series must be at least 1");
  if (choices.delay < 1)
    throw std::invalid_argument("kantz_options: delay must be at least 1 sample");
  if (choices.dimension && *choices.dimension < 1)
    throw std::invalid_argument("kantz_options: dimension must be at least 1");
  series_lyapunov_options options;
  auto& s = options.stretching;
  s.delay = choices.delay;
  s.dimension = choices.dimension ? *choices.dimension : kantz_dimension(series);
  // The embedding window: neighbours closer in time lie on the same piece of trajectory.
  s.theiler_window = choices.theiler_window ? *choices.theiler_window
                                            : std::max<std::size_t>(1, s.dimension - 1) * s.delay;
  s.horizon = choices.horizon ? *choices.horizon : std::min<std::size_t>(40 * s.delay, samples / 4);
  s.horizon = std::max<std::size_t>(s.horizon, 2);
  s.step = std::max<std::size_t>(1, s.horizon / 200);
  s.radii = choices.radii;
  options.fit_from = choices.fit_from;
  options.fit_to = choices.fit_to;
  return options;
}

series_lyapunov_result series_lyapunov_exponent(std::span<const double> x, double dt,
                                                const series_lyapunov_options& o) {
  check_fit_options(dt, o);
  return fit_stretching(stretching_curves(x, o.stretching), dt, o);
}

series_lyapunov_result series_lyapunov_exponent(std::span<const std::vector<double>> series,
                                                double dt, const series_lyapunov_options& o) {
  check_fit_options(dt, o);
  return fit_stretching(stretching_curves(series, o.stretching), dt, o);
}

}  // namespace npend
