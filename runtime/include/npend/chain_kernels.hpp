// The contract between the generated kernels and the runtime: how states and parameters are
// laid out, and the table of functions every generated link count provides.
//
// The generator (npend-gen) includes this header too, so the layout it emits indices for is
// the one the runtime packs, and each generated chain_<n>.cpp fills its table entry by the
// field names below: a kernel the table does not know, or a signature that differs, fails
// to compile instead of being called wrongly. The header is self-contained (no library, no
// generated code) for that reason.
#pragma once

#include <cstddef>

namespace npend {

/// Where the coordinates and parameters of an n-link chain sit in the flat arrays the
/// kernels take (indices 0-based).
namespace chain_layout {

/// The most links npend-gen derives (the runtime sizes its input buffers by it).
constexpr int max_links = 64;

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
constexpr int com_index(int n, int i) { return 2 * n + 1 + i; }
constexpr int inertia_index(int n, int i) { return 3 * n + 1 + i; }

/// Physical chains extend them again: params = [m, l, g, c, J, k_1..k_n, θ⁰_1..θ⁰_n,
/// b_1..b_n] — joint spring stiffnesses (N m/rad), their rest angles (rad) and joint damping
/// coefficients (N m s/rad), joint j joining link j−1 to link j.
constexpr int physical_param_size(int n) { return 7 * n + 1; }
constexpr int stiffness_index(int n, int i) { return 4 * n + 1 + i; }
constexpr int rest_angle_index(int n, int i) { return 5 * n + 1 + i; }
constexpr int damping_index(int n, int i) { return 6 * n + 1 + i; }

/// The time-dependent inputs of physical chains, w = [a_x, a_y, u_1..u_n]: the pivot's
/// acceleration (m/s², x right, y down) and the motor torque at each joint (N m, acting on
/// link j with its reaction on link j−1).
constexpr int input_size(int n) { return n + 2; }
constexpr int pivot_acceleration_index(int axis) { return axis; }  ///< axis 0 = x, 1 = y
constexpr int torque_index(int /*n*/, int i) { return 2 + i; }

}  // namespace chain_layout

/// The pendulum chain on a cart: the physical chain hung from a cart of mass M that slides on
/// a horizontal line (a prismatic joint under the pivot), pushed by a horizontal force F and
/// slowed by viscous damping b_x (force −b_x ẋ). The generalised coordinates are
/// q = [x, φ_1..φ_n] (x the cart's position, m, to the right; angles as for the chain), so
/// the functions of physical_kernels that take "phi" take these n + 1 coordinates. Link k's
/// end sits at (x + Σ_{i≤k} l_i sin φ_i, Σ_{i≤k} l_i cos φ_i), y down as for the chain.
namespace cart_layout {

/// Generalised coordinates q = [x, φ_1..φ_n] (dim n + 1).
constexpr int coordinate_count(int n) { return n + 1; }

/// x = [x_cart, φ_1..φ_n, p_x, p_1..p_n]: the cart's position and the angles, then their
/// momenta (p_x = ∂L/∂ẋ, the total horizontal momentum).
constexpr int state_size(int n) { return 2 * (n + 1); }
constexpr int cart_position_index = 0;
constexpr int angle_index(int /*n*/, int i) { return 1 + i; }
constexpr int cart_momentum_index(int n) { return n + 1; }
constexpr int momentum_index(int n, int i) { return n + 2 + i; }

/// params = the physical chain's (chain_layout::physical_param_size(n), at the same
/// positions) followed by [M, b_x]: the cart's mass (kg) and its viscous damping (N s/m).
constexpr int param_size(int n) { return 7 * n + 3; }
constexpr int cart_mass_index(int n) { return 7 * n + 1; }
constexpr int cart_damping_index(int n) { return 7 * n + 2; }

/// Inputs w = [F, u_1..u_n]: the horizontal force on the cart (N, to the right) and the
/// joint torques (N m). There is no pivot acceleration: the pivot is the cart.
constexpr int input_size(int n) { return n + 1; }
constexpr int force_index = 0;
constexpr int torque_index(int /*n*/, int i) { return 1 + i; }

}  // namespace cart_layout

namespace taylor {
struct dual;  // npend/integrators/taylor_recurrences.hpp
}  // namespace taylor

/// The Taylor coefficients of one model's solution for one link count (generated
/// taylor_<stem>_<n>.hpp): coefficients(params, inputs, order, series, work) fills
/// series[i·(order+1) + k], k = 1..order, the coefficient of τ^k in x_i(t + τ), from the
/// state in k = 0, by the recurrences of automatic differentiation over the equations'
/// nodes. inputs holds the series of the time-dependent inputs w the same way (k <
/// order; not read by models without inputs), work work_slots·(order + 1) numbers. The
/// long double version is the same recurrences in long double; the dual one the same on dual
/// numbers, whose derivatives carry the coefficients of a tangent vector (the variational
/// equations; taylor::dual), params and inputs as constants (no derivative).
struct taylor_kernels {
  int state_size;
  int param_size;
  int input_size;
  int work_slots;
  void (*coefficients)(const double* params, const double* inputs, int order, double* series,
                       double* work) noexcept;
  void (*coefficients_long)(const long double* params, const long double* inputs, int order,
                            long double* series, long double* work) noexcept;
  void (*coefficients_dual)(const taylor::dual* params, const taylor::dual* inputs, int order,
                            taylor::dual* series, taylor::dual* work) noexcept;
};

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
  /// The Taylor kernels of the same equations.
  const taylor_kernels* taylor = nullptr;
};

/// The emitted functions of one link count of the physical chain (rigid links, joint springs,
/// damping and torques, a moving pivot; see generated physical_<n>.hpp). Parameters as
/// chain_layout::physical_param_size, inputs w as chain_layout::input_size. The functions
/// that depend on w take it; the others are those of chain_kernels.
///
/// The chain on a cart (generated cart_<n>.hpp) fills the same table with cart_layout's
/// sizes: its "phi" are the n + 1 coordinates q = [x, φ_1..φ_n], the mass matrix and
/// potential Hessian are (n+1) × (n+1), the Jacobian (2n+2)², input_matrix 2(n+1) × (n+1),
/// positions the cart's (x, 0) then the n bobs' (x, y), 2(n+1) numbers, and
/// hamiltonian = T + V.
struct physical_kernels {
  int links;
  int state_size;
  int param_size;
  int input_size;
  void (*rhs)(const double* x, const double* params, const double* inputs, double* dxdt) noexcept;
  void (*jacobian)(const double* x, const double* params, const double* inputs,
                   double* jac) noexcept;
  double (*hamiltonian)(const double* x, const double* params, const double* inputs) noexcept;
  void (*velocities)(const double* phi, const double* p, const double* params,
                     double* dphi) noexcept;
  void (*momenta)(const double* phi, const double* dphi, const double* params, double* p) noexcept;
  double (*lagrangian)(const double* phi, const double* dphi, const double* params,
                       const double* inputs) noexcept;
  double (*kinetic_energy)(const double* phi, const double* dphi, const double* params) noexcept;
  double (*potential_energy)(const double* phi, const double* params,
                             const double* inputs) noexcept;
  void (*mass_matrix)(const double* phi, const double* params, double* A) noexcept;
  double (*det_mass_matrix)(const double* phi, const double* params) noexcept;
  void (*potential_gradient)(const double* phi, const double* params, const double* inputs,
                             double* grad) noexcept;
  void (*potential_hessian)(const double* phi, const double* params, const double* inputs,
                            double* hess) noexcept;
  void (*positions)(const double* phi, const double* params, double* xy) noexcept;
  /// ∂f/∂w, row-major state_size × input_size (2n × (n + 2) for the physical chain).
  void (*input_matrix)(const double* phi, const double* params, double* dfdw) noexcept;
  const char* (*equations_latex)() noexcept = nullptr;
  /// The Taylor kernels of the same equations (inputs: the series of w).
  const taylor_kernels* taylor = nullptr;
};

/// The loop kernels (generated/chain_loop.*): the point-mass chain's functions for any link
/// count n, as loops over the links, for the counts without unrolled kernels. Each takes n
/// first and a workspace of workspace_size(n) doubles last (jacobian_workspace_size(n) for
/// the Jacobian); the functions are those of chain_kernels, plus J(x)·u in O(n).
struct loop_kernels {
  int (*workspace_size)(int n) noexcept;
  std::size_t (*jacobian_workspace_size)(int n) noexcept;
  void (*rhs)(int n, const double* x, const double* params, double* dxdt, double* work) noexcept;
  void (*jacobian_vector)(int n, const double* x, const double* params, const double* u, double* ju,
                          double* work) noexcept;
  void (*jacobian)(int n, const double* x, const double* params, double* jac,
                   double* work) noexcept;
  double (*hamiltonian)(int n, const double* x, const double* params, double* work) noexcept;
  void (*velocities)(int n, const double* phi, const double* p, const double* params, double* dphi,
                     double* work) noexcept;
  void (*momenta)(int n, const double* phi, const double* dphi, const double* params, double* p,
                  double* work) noexcept;
  double (*kinetic_energy)(int n, const double* phi, const double* dphi, const double* params,
                           double* work) noexcept;
  double (*potential_energy)(int n, const double* phi, const double* params, double* work) noexcept;
  double (*lagrangian)(int n, const double* phi, const double* dphi, const double* params,
                       double* work) noexcept;
  void (*mass_matrix)(int n, const double* phi, const double* params, double* A,
                      double* work) noexcept;
  double (*det_mass_matrix)(int n, const double* phi, const double* params, double* work) noexcept;
  double (*log_det_mass_matrix)(int n, const double* phi, const double* params,
                                double* work) noexcept;
  void (*potential_gradient)(int n, const double* phi, const double* params, double* grad,
                             double* work) noexcept;
  void (*potential_hessian)(int n, const double* phi, const double* params, double* hess,
                            double* work) noexcept;
  void (*positions)(int n, const double* phi, const double* params, double* xy,
                    double* work) noexcept;
};

}  // namespace npend
