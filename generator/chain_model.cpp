#include "chain_model.hpp"

#include <stdexcept>
#include <string>

namespace npend::gen {

namespace {

std::vector<GiNaC::realsymbol> indexed_symbols(const std::string& stem, int n) {
  std::vector<GiNaC::realsymbol> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 1; i <= n; ++i) out.emplace_back(stem + std::to_string(i));
  return out;
}

std::size_t u(int i) { return static_cast<std::size_t>(i); }

}  // namespace

const char* link_kind_name(link_kind kind) {
  switch (kind) {
    case link_kind::point_mass:
      return "point";
    case link_kind::rigid:
      return "rigid";
    case link_kind::physical:
      return "physical";
    case link_kind::cart:
      return "cart";
  }
  return "?";
}

chain_symbols::chain_symbols(int links, link_kind kind_)
    : n(links),
      kind(kind_),
      phi(indexed_symbols("phi", links)),
      dphi(indexed_symbols("dphi", links)),
      ddphi(indexed_symbols("ddphi", links)),
      p(indexed_symbols("p", links)),
      mass(indexed_symbols("m", links)),
      length(indexed_symbols("l", links)),
      com(indexed_symbols("com", links)),
      inertia(indexed_symbols("J", links)),
      stiffness(indexed_symbols("k", links)),
      rest_angle(indexed_symbols("rest", links)),
      damping(indexed_symbols("b", links)),
      torque(indexed_symbols("u", links)),
      drive_x("ax"),
      drive_y("ay"),
      mu(indexed_symbols("mu", links)),
      g("g"),
      s(indexed_symbols("s", links)),
      c(indexed_symbols("c", links)),
      cart_x("x"),
      cart_dx("dx"),
      cart_ddx("ddx"),
      cart_p("px"),
      cart_mass("M"),
      cart_damping("bx"),
      cart_force("F") {
  if (links < 1) throw std::invalid_argument("chain_symbols: links must be >= 1");
  if (on_cart(kind)) coords = {{cart_x}, {cart_dx}, {cart_ddx}, {cart_p}};
  coords.q.insert(coords.q.end(), phi.begin(), phi.end());
  coords.dq.insert(coords.dq.end(), dphi.begin(), dphi.end());
  coords.ddq.insert(coords.ddq.end(), ddphi.begin(), ddphi.end());
  coords.p.insert(coords.p.end(), p.begin(), p.end());
}

lagrangian_model chain_kinematics(const chain_symbols& sym, const GiNaC::ex& pivot_x,
                                  chain_mechanics& mech) {
  const int n = sym.n;

  // Kinematics (eq. 6.1): each rod adds l_i (sin φ_i, cos φ_i) to the previous bob.
  GiNaC::ex x = pivot_x, y = 0;
  for (int k = 0; k < n; ++k) {
    x += sym.length[u(k)] * GiNaC::sin(sym.phi[u(k)]);
    y += sym.length[u(k)] * GiNaC::cos(sym.phi[u(k)]);
    mech.x.push_back(x);
    mech.y.push_back(y);
  }

  // Energies: T = Σ m_k/2 |ṙ_k|² (+ J_k/2 φ̇_k² for a rigid link's rotation about its centre
  // of mass, König), V = Σ m_k g (rest depth − depth) of each mass point r_k.
  //
  // A moving pivot r₀(t) is taken in its own frame: the lab-frame Lagrangian's cross term
  // Σ m_k ṙ₀·ρ̇_k is d/dt(Σ m_k ṙ₀·ρ_k) − Σ m_k r̈₀·ρ_k, and dropping the total derivative and
  // the function of t alone leaves the fixed-pivot T and the potential of the inertial force,
  // Σ m_k a·ρ_k with a = r̈₀: gravity g becomes g − a_y and a_x adds a horizontal field.
  const bool rigid = has_rigid_links(sym.kind);
  const bool joints = has_joint_forces(sym.kind);
  const bool drive = has_pivot_drive(sym.kind);
  const GiNaC::ex gravity = drive ? sym.g - sym.drive_y : GiNaC::ex(sym.g);
  GiNaC::ex T = 0, V = 0, joint_depth = 0;
  for (int k = 0; k < n; ++k) {
    // The mass point: the bob, or the centre of mass c_k down link k from joint k.
    const GiNaC::ex reach = rigid ? GiNaC::ex(sym.com[u(k)]) : GiNaC::ex(sym.length[u(k)]);
    const GiNaC::ex above_x = k > 0 ? mech.x[u(k - 1)] : pivot_x;
    const GiNaC::ex above_y = k > 0 ? mech.y[u(k - 1)] : GiNaC::ex(0);
    const GiNaC::ex rx = above_x + reach * GiNaC::sin(sym.phi[u(k)]);
    const GiNaC::ex ry = above_y + reach * GiNaC::cos(sym.phi[u(k)]);
    const GiNaC::ex vx = time_derivative(sym, rx);
    const GiNaC::ex vy = time_derivative(sym, ry);
    T += sym.mass[u(k)] / 2 * (vx * vx + vy * vy);
    if (rigid) T += sym.inertia[u(k)] / 2 * sym.dphi[u(k)] * sym.dphi[u(k)];
    V += sym.mass[u(k)] * gravity * (joint_depth + reach - ry);
    if (drive) V += sym.mass[u(k)] * sym.drive_x * rx;
    joint_depth += sym.length[u(k)];
  }
  // Joints: θ_j = φ_j − φ_{j−1}; springs ½ k_j (θ_j − θ_j⁰)² in V, damping in the Rayleigh
  // function R = ½ Σ b_j θ̇_j², and the torque u_j doing the virtual work u_j δθ_j.
  GiNaC::ex R = 0, torque_work = 0;
  for (int j = 0; j < n; ++j) {
    const GiNaC::ex theta = j > 0 ? sym.phi[u(j)] - sym.phi[u(j - 1)] : GiNaC::ex(sym.phi[0]);
    mech.joint_angle.push_back(theta);
    if (!joints) continue;
    const GiNaC::ex stretch = theta - sym.rest_angle[u(j)];
    V += sym.stiffness[u(j)] / 2 * stretch * stretch;
    const GiNaC::ex rate = time_derivative(sym, theta);
    R += sym.damping[u(j)] / 2 * rate * rate;
    torque_work += sym.torque[u(j)] * theta;
  }
  return {T, V, R, torque_work};
}

chain_mechanics derive_mechanics(const chain_symbols& sym) {
  if (on_cart(sym.kind)) return derive_cart_mechanics(sym);
  chain_mechanics mech;
  const lagrangian_model model = chain_kinematics(sym, 0, mech);
  static_cast<lagrangian_mechanics&>(mech) = derive_lagrangian_mechanics(sym.coords, model);
  return mech;
}

}  // namespace npend::gen
