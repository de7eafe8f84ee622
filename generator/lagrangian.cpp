#include "lagrangian.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

}  // namespace

GiNaC::ex time_derivative(const coordinates& q, const GiNaC::ex& e) {
  GiNaC::ex d = 0;
  for (int i = 0; i < q.size(); ++i) {
    d += e.diff(q.q[u(i)]) * q.dq[u(i)];
    d += e.diff(q.dq[u(i)]) * q.ddq[u(i)];
  }
  return d;
}

lagrangian_mechanics derive_lagrangian_mechanics(const coordinates& q,
                                                 const lagrangian_model& model) {
  const int n = q.size();
  lagrangian_mechanics mech;
  mech.rayleigh = model.rayleigh.expand();
  mech.kinetic = model.kinetic.expand();
  mech.potential = model.potential.expand();
  mech.lagrangian = mech.kinetic - mech.potential;

  // Legendre transform: momenta and the mass matrix as derivatives of L.
  mech.mass_matrix = GiNaC::matrix(u(n), u(n));
  mech.hess_potential = GiNaC::matrix(u(n), u(n));
  for (int i = 0; i < n; ++i) {
    mech.momenta.push_back(mech.lagrangian.diff(q.dq[u(i)]));
    mech.dL_dphi.push_back(mech.lagrangian.diff(q.q[u(i)]));
    mech.grad_potential.push_back(mech.potential.diff(q.q[u(i)]));
    mech.force.push_back(
        (model.input_work.diff(q.q[u(i)]) - mech.rayleigh.diff(q.dq[u(i)])).expand());
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      mech.mass_matrix(u(i), u(j)) = mech.momenta[u(i)].diff(q.dq[u(j)]);
      mech.hess_potential(u(i), u(j)) = mech.grad_potential[u(i)].diff(q.q[u(j)]);
    }
  return mech;
}

std::vector<GiNaC::matrix> mass_matrix_derivatives(const coordinates& q,
                                                   const lagrangian_mechanics& mech) {
  std::vector<GiNaC::matrix> out;
  const auto n = u(q.size());
  for (std::size_t k = 0; k < n; ++k) {
    GiNaC::matrix d(n, n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) d(i, j) = mech.mass_matrix(i, j).diff(q.q[k]);
    out.push_back(d);
  }
  return out;
}

lagrangian_hessians derive_lagrangian_hessians(const coordinates& q,
                                               const lagrangian_mechanics& mech) {
  const auto n = u(q.size());
  lagrangian_hessians h{GiNaC::matrix(n, n), GiNaC::matrix(n, n), GiNaC::matrix(n, n)};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      h.phi_phi(i, j) = mech.dL_dphi[i].diff(q.q[j]);
      h.phi_dphi(i, j) = mech.dL_dphi[i].diff(q.dq[j]);
      h.force_dphi(i, j) = mech.force[i].diff(q.dq[j]);
      if (!h.force_dphi(i, j).is_zero()) h.has_damping = true;
    }
  return h;
}

closed_form_hamiltonian derive_closed_form_hamiltonian(const coordinates& q,
                                                       const lagrangian_mechanics& mech) {
  const auto n = u(q.size());
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
    for (std::size_t j = 0; j < n; ++j) numerator += q.p[i] * adj(i, j) * q.p[j];
  return {numerator.expand(), mech.mass_matrix.determinant(GiNaC::determinant_algo::laplace),
          mech.potential};
}

}  // namespace npend::gen
