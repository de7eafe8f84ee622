// The pendulum chain on a cart, the classic control benchmark: the physical chain's links hung
// from a cart of mass M that slides on a horizontal rail (a prismatic joint under the pivot),
// pushed by a horizontal force F and slowed by viscous damping b_x. This file is the whole
// model: the cart's terms on top of the chain's kinematics; the mechanics are generic
// (lagrangian.hpp).
#include "chain_model.hpp"

namespace npend::gen {

chain_mechanics derive_cart_mechanics(const chain_symbols& sym) {
  chain_mechanics mech;
  // The pivot is the cart at (x, 0): every mass point moves with ẋ too, which the chain's
  // T = Σ m_k/2 |ṙ_k|² picks up through the coordinates q = [x, φ].
  lagrangian_model model = chain_kinematics(sym, sym.cart_x, mech);
  model.kinetic += sym.cart_mass / 2 * sym.cart_dx * sym.cart_dx;
  model.rayleigh += sym.cart_damping / 2 * sym.cart_dx * sym.cart_dx;
  model.input_work += sym.cart_force * sym.cart_x;
  static_cast<lagrangian_mechanics&>(mech) = derive_lagrangian_mechanics(sym.coords, model);
  return mech;
}

}  // namespace npend::gen
