// The contract between the generated kernels and the runtime: how states and parameters are
// laid out, and the table of functions every generated link count provides.
//
// The generator (npend-gen) includes this header too, so the layout it emits indices for is
// the one the runtime packs, and each generated chain_<n>.cpp fills its table entry by the
// field names below: a kernel the table does not know, or a signature that differs, fails
// to compile instead of being called wrongly. The header is self-contained (no library, no
// generated code) for that reason.
#pragma once

namespace npend {

/// Where the coordinates and parameters of an n-link chain sit in the flat arrays the
/// kernels take (indices 0-based).
namespace chain_layout {

/// x = [φ_1..φ_n, p_1..p_n]: angles from the downward vertical, then their momenta.
constexpr int state_size(int n) { return 2 * n; }
constexpr int angle_index(int /*n*/, int i) { return i; }
constexpr int momentum_index(int n, int i) { return n + i; }

/// params = [m_1..m_n, l_1..l_n, g].
constexpr int param_size(int n) { return 2 * n + 1; }
constexpr int mass_index(int /*n*/, int i) { return i; }
constexpr int length_index(int n, int i) { return n + i; }
constexpr int gravity_index(int n) { return 2 * n; }

/// Rigid links extend the parameters: params = [m_1..m_n, l_1..l_n, g, c_1..c_n, J_1..J_n]
/// (centre-of-mass distances from the upper joint, moments of inertia about the centre of
/// mass), so that the point-mass layout is their first 2n + 1 entries.
constexpr int rigid_param_size(int n) { return 4 * n + 1; }
constexpr int com_index(int n, int i) { return 2 * n + 1 + i; }
constexpr int inertia_index(int n, int i) { return 3 * n + 1 + i; }

}  // namespace chain_layout

/// The emitted functions of one link count (see generated chain_<n>.hpp for each one's
/// formula). All take the layout of chain_layout; none allocates or throws.
struct chain_kernels {
  int links;
  int state_size;  ///< chain_layout::state_size(links), as the generator emitted it
  int param_size;  ///< chain_layout::param_size(links), as the generator emitted it
  void (*rhs)(const double* x, const double* params, double* dxdt) noexcept;
  void (*jacobian)(const double* x, const double* params, double* jac) noexcept;
  double (*hamiltonian)(const double* x, const double* params) noexcept;
  void (*velocities)(const double* phi, const double* p, const double* params,
                     double* dphi) noexcept;
  void (*momenta)(const double* phi, const double* dphi, const double* params, double* p) noexcept;
  double (*lagrangian)(const double* phi, const double* dphi, const double* params) noexcept;
  double (*kinetic_energy)(const double* phi, const double* dphi, const double* params) noexcept;
  double (*potential_energy)(const double* phi, const double* params) noexcept;
  void (*mass_matrix)(const double* phi, const double* params, double* A) noexcept;
  double (*det_mass_matrix)(const double* phi, const double* params) noexcept;
  void (*potential_gradient)(const double* phi, const double* params, double* grad) noexcept;
  void (*potential_hessian)(const double* phi, const double* params, double* hess) noexcept;
  void (*positions)(const double* phi, const double* params, double* xy) noexcept;
  /// Closed-form Hamiltonian (for checking against the paper); nullptr where it is not
  /// emitted (more than 3 links).
  double (*hamiltonian_closed_form)(const double* x, const double* params) noexcept = nullptr;
  /// The derived equations as LaTeX.
  const char* (*equations_latex)() noexcept = nullptr;
};

}  // namespace npend
