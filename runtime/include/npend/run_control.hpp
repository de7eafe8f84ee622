// How a long computation tells its caller how far it got, and learns that it should stop.
#pragma once

#include <cstddef>

namespace npend {

/// The caller's side of a long computation: integrations, Poincaré sections, Lyapunov
/// exponents, backbone curves and sampled series report their progress here and poll it
/// for a stop request (Ctrl-C, a time limit, a condition the caller watches). One object
/// serves every computation, so a front end writes its progress bar and interrupt handling
/// once. Pass it through `integration_options::control`; it is not owned and may be null.
///
/// A computation that is asked to stop finishes its current step and returns what it has,
/// flagged as stopped (e.g. integration_result::stopped); it does not throw.
class run_control {
 public:
  virtual ~run_control() = default;

  /// The computation has done `done` of `total` units of work (its own units, e.g.
  /// seconds of simulated time), 0 ≤ done ≤ total. Called often: keep it cheap.
  virtual void progress(double done, double total) {
    static_cast<void>(done);
    static_cast<void>(total);
  }

  /// Polled as often as progress(): true asks the computation to stop.
  virtual bool stop_requested() { return false; }
};

/// Reports progress to `control` and returns whether it asks to stop; a null control
/// neither hears nor asks anything.
inline bool report_progress(run_control* control, double done, double total) {
  if (control == nullptr) return false;
  control->progress(done, total);
  return control->stop_requested();
}

/// Whether `control` asks to stop (never, when it is null).
inline bool stop_requested(run_control* control) {
  return control != nullptr && control->stop_requested();
}

/// Part `index` of `parts` equal parts of the parent's work (an ensemble member, one of a
/// series of integrations): maps the part's own progress into the parent's, and passes the
/// stop requests through. A null parent gives a control that does nothing.
class run_control_part final : public run_control {
 public:
  run_control_part(run_control* parent, std::size_t index, std::size_t parts)
      : m_parent(parent),
        m_index(static_cast<double>(index)),
        m_parts(static_cast<double>(parts)) {}

  void progress(double done, double total) override {
    if (m_parent != nullptr && total > 0) m_parent->progress(m_index + done / total, m_parts);
  }
  bool stop_requested() override { return npend::stop_requested(m_parent); }

 private:
  run_control* m_parent;
  double m_index, m_parts;
};

}  // namespace npend
