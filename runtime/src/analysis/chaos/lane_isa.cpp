// Which ISA's lanes the maps run on (detail::map_lanes, map_lanes.hpp): the variants the
// build compiled (cmake/npend_lanes.cmake) that the CPU has, picked once, or on request.
#include <fmt/format.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/chaos/map_lanes.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/batch_math.hpp"

// A variant's lanes exist where the build compiled variants and the variant lies above the
// compiler's own ISA (below it, its unit is empty).
#if defined(NPEND_LANE_VARIANTS) && NPEND_LANE_AVX2 > NPEND_LANE_BASELINE
#define NPEND_HAS_AVX2_LANES 1
#endif
#if defined(NPEND_LANE_VARIANTS) && NPEND_LANE_AVX512F > NPEND_LANE_BASELINE
#define NPEND_HAS_AVX512F_LANES 1
#endif

namespace npend::detail {

// Each defined in map_lanes.cpp, compiled for the ISA of its namespace.
inline namespace NPEND_BATCH_ISA_NAMESPACE {
const map_lanes& lanes_of_this_isa();
}
#ifdef NPEND_HAS_AVX2_LANES
namespace isa_avx2 {
const map_lanes& lanes_of_this_isa();
}
#endif
#ifdef NPEND_HAS_AVX512F_LANES
namespace isa_avx512f {
const map_lanes& lanes_of_this_isa();
}
#endif

namespace {

// The lanes the build has and the CPU runs, lowest ISA first. __builtin_cpu_supports also
// asks whether the operating system saves the wider registers.
std::vector<const map_lanes*> runnable_lanes() {
  std::vector<const map_lanes*> out{&lanes_of_this_isa()};
  __builtin_cpu_init();
#ifdef NPEND_HAS_AVX2_LANES
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    out.push_back(&isa_avx2::lanes_of_this_isa());
#endif
#ifdef NPEND_HAS_AVX512F_LANES
  if (__builtin_cpu_supports("avx512f")) out.push_back(&isa_avx512f::lanes_of_this_isa());
#endif
  return out;
}

const std::vector<const map_lanes*>& runnable() {
  static const std::vector<const map_lanes*> lanes = runnable_lanes();
  return lanes;
}

const map_lanes* find_lanes(std::string_view isa) {
  for (const map_lanes* lanes : runnable())
    if (isa == lanes->isa) return lanes;
  return nullptr;
}

std::string runnable_names() {
  std::string names;
  for (const map_lanes* lanes : runnable())
    names += (names.empty() ? "" : ", ") + std::string(lanes->isa);
  return names;
}

const map_lanes& initial_lanes() {
  const char* asked = std::getenv("NPEND_LANE_ISA");
  if (asked == nullptr || *asked == '\0') return *runnable().back();
  if (const map_lanes* lanes = find_lanes(asked)) return *lanes;
  throw std::invalid_argument(
      fmt::format("NPEND_LANE_ISA: the maps' lanes run on one of {} on this machine, not '{}'",
                  runnable_names(), asked));
}

std::atomic<const map_lanes*> chosen{nullptr};

}  // namespace

const map_lanes& active_map_lanes() {
  const map_lanes* lanes = chosen.load(std::memory_order_acquire);
  if (lanes != nullptr) return *lanes;
  const map_lanes* expected = nullptr;
  chosen.compare_exchange_strong(expected, &initial_lanes(), std::memory_order_acq_rel);
  return *chosen.load(std::memory_order_acquire);
}

}  // namespace npend::detail

namespace npend {

std::vector<std::string_view> batch_lane_isas() {
  std::vector<std::string_view> names;
  for (const detail::map_lanes* lanes : detail::runnable()) names.emplace_back(lanes->isa);
  return names;
}

std::string_view batch_lane_isa() { return detail::active_map_lanes().isa; }

void use_batch_lane_isa(std::string_view isa) {
  const detail::map_lanes* lanes = detail::find_lanes(isa);
  if (lanes == nullptr)
    throw std::invalid_argument(
        fmt::format("lane ISA: the maps' lanes run on one of {} on this machine, not '{}'",
                    detail::runnable_names(), isa));
  detail::chosen.store(lanes, std::memory_order_release);
}

}  // namespace npend
