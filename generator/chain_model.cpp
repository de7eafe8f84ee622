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
      c(indexed_symbols("c", links)) {
  if (links < 1) throw std::invalid_argument("chain_symbols: links must be >= 1");
}

GiNaC::ex time_derivative(const chain_symbols& sym, const GiNaC::ex& e) {
  GiNaC::ex d = 0;
  for (int i = 0; i < sym.n; ++i) {
    d += e.diff(sym.phi[u(i)]) * sym.dphi[u(i)];
    d += e.diff(sym.dphi[u(i)]) * sym.ddphi[u(i)];
  }
  return d;
}

chain_mechanics derive_mechanics(const chain_symbols& sym) {
  const int n = sym.n;
  chain_mechanics mech;

  // Kinematics (eq. 6.1): each rod adds l_i (sin φ_i, cos φ_i) to the previous bob.
  GiNaC::ex x = 0, y = 0;
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
  const bool physical = sym.kind == link_kind::physical;
  const GiNaC::ex gravity = physical ? sym.g - sym.drive_y : GiNaC::ex(sym.g);
  GiNaC::ex T = 0, V = 0, joint_depth = 0;
  for (int k = 0; k < n; ++k) {
    // The mass point: the bob, or the centre of mass c_k down link k from joint k.
    const GiNaC::ex reach = rigid ? GiNaC::ex(sym.com[u(k)]) : GiNaC::ex(sym.length[u(k)]);
    const GiNaC::ex above_x = k > 0 ? mech.x[u(k - 1)] : GiNaC::ex(0);
    const GiNaC::ex above_y = k > 0 ? mech.y[u(k - 1)] : GiNaC::ex(0);
    const GiNaC::ex rx = above_x + reach * GiNaC::sin(sym.phi[u(k)]);
    const GiNaC::ex ry = above_y + reach * GiNaC::cos(sym.phi[u(k)]);
    const GiNaC::ex vx = time_derivative(sym, rx);
    const GiNaC::ex vy = time_derivative(sym, ry);
    T += sym.mass[u(k)] / 2 * (vx * vx + vy * vy);
    if (rigid) T += sym.inertia[u(k)] / 2 * sym.dphi[u(k)] * sym.dphi[u(k)];
    V += sym.mass[u(k)] * gravity * (joint_depth + reach - ry);
    if (physical) V += sym.mass[u(k)] * sym.drive_x * rx;
    joint_depth += sym.length[u(k)];
  }
  // Joints: θ_j = φ_j − φ_{j−1}; springs ½ k_j (θ_j − θ_j⁰)² in V, damping in the Rayleigh
  // function R = ½ Σ b_j θ̇_j², and the torque u_j doing the virtual work u_j δθ_j.
  GiNaC::ex R = 0, torque_work = 0;
  for (int j = 0; j < n; ++j) {
    const GiNaC::ex theta = j > 0 ? sym.phi[u(j)] - sym.phi[u(j - 1)] : GiNaC::ex(sym.phi[0]);
    mech.joint_angle.push_back(theta);
    if (!physical) continue;
    const GiNaC::ex stretch = theta - sym.rest_angle[u(j)];
    V += sym.stiffness[u(j)] / 2 * stretch * stretch;
    const GiNaC::ex rate = time_derivative(sym, theta);
    R += sym.damping[u(j)] / 2 * rate * rate;
    torque_work += sym.torque[u(j)] * theta;
  }
  mech.rayleigh = R.expand();
  mech.kinetic = T.expand();
  mech.potential = V.expand();
  mech.lagrangian = mech.kinetic - mech.potential;

  // Legendre transform: momenta and the mass matrix as derivatives of L.
  mech.mass_matrix = GiNaC::matrix(u(n), u(n));
  mech.hess_potential = GiNaC::matrix(u(n), u(n));
  for (int i = 0; i < n; ++i) {
    mech.momenta.push_back(mech.lagrangian.diff(sym.dphi[u(i)]));
    mech.dL_dphi.push_back(mech.lagrangian.diff(sym.phi[u(i)]));
    mech.grad_potential.push_back(mech.potential.diff(sym.phi[u(i)]));
    mech.force.push_back(
        (torque_work.diff(sym.phi[u(i)]) - mech.rayleigh.diff(sym.dphi[u(i)])).expand());
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      mech.mass_matrix(u(i), u(j)) = mech.momenta[u(i)].diff(sym.dphi[u(j)]);
      mech.hess_potential(u(i), u(j)) = mech.grad_potential[u(i)].diff(sym.phi[u(j)]);
    }
  return mech;
}

std::vector<GiNaC::matrix> mass_matrix_derivatives(const chain_symbols& sym,
                                                   const chain_mechanics& mech) {
  std::vector<GiNaC::matrix> out;
  const auto n = u(sym.n);
  for (std::size_t k = 0; k < n; ++k) {
    GiNaC::matrix d(n, n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) d(i, j) = mech.mass_matrix(i, j).diff(sym.phi[k]);
    out.push_back(d);
  }
  return out;
}

lagrangian_hessians derive_lagrangian_hessians(const chain_symbols& sym,
                                               const chain_mechanics& mech) {
  const auto n = u(sym.n);
  lagrangian_hessians h{GiNaC::matrix(n, n), GiNaC::matrix(n, n), GiNaC::matrix(n, n)};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      h.phi_phi(i, j) = mech.dL_dphi[i].diff(sym.phi[j]);
      h.phi_dphi(i, j) = mech.dL_dphi[i].diff(sym.dphi[j]);
      h.force_dphi(i, j) = mech.force[i].diff(sym.dphi[j]);
      if (!h.force_dphi(i, j).is_zero()) h.has_damping = true;
    }
  return h;
}

closed_form_hamiltonian derive_closed_form_hamiltonian(const chain_symbols& sym,
                                                       const chain_mechanics& mech) {
  const auto n = u(sym.n);
  // adj(A)_ij = (−1)^{i+j} M_ji with M the minors; for small n a cofactor expansion of the
  // (already polynomial) entries is cheap, and it avoids normal() on a rational inverse.
  GiNaC::matrix adj(n, n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      if (n == 1) {
        adj(i, j) = 1;
        continue;
      }
      GiNaC::matrix minor(n - 1, n - 1);
      for (std::size_t r = 0, rr = 0; r < n; ++r) {
        if (r == j) continue;
        for (std::size_t col = 0, cc = 0; col < n; ++col) {
          if (col == i) continue;
          minor(rr, cc++) = mech.mass_matrix(r, col);
        }
        ++rr;
      }
      const int sign = ((i + j) % 2 == 0) ? 1 : -1;
      adj(i, j) = sign * minor.determinant(GiNaC::determinant_algo::laplace);
    }
  GiNaC::ex numerator = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) numerator += sym.p[i] * adj(i, j) * sym.p[j];
  return {numerator.expand(), mech.mass_matrix.determinant(GiNaC::determinant_algo::laplace),
          mech.potential};
}

}  // namespace npend::gen
