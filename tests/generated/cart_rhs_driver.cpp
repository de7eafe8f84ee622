// Prints the generated rhs of the chain on a cart for the states the caller gives, so that a
// script with an independent derivation (cart_sympy_check.py) can compare them.
//
// Each line of stdin: n, then params (cart_layout::param_size(n)), the state x
// (cart_layout::state_size(n)) and the inputs w (cart_layout::input_size(n)). Each line of
// stdout: dxdt, state_size(n) numbers to 17 significant digits. Exit 2 on a malformed line or
// a link count without kernels.
#include <chain_index.hpp>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

int main() {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    int n = 0;
    if (!(in >> n)) continue;
    const npend::physical_kernels* k = npend::generated::cart_kernels_for(n);
    if (k == nullptr) {
      std::cerr << "cart_rhs_driver: no kernels for " << n << " links on a cart\n";
      return 2;
    }
    const auto read = [&](int count) {
      std::vector<double> v(static_cast<std::size_t>(count));
      for (double& d : v) in >> d;
      return v;
    };
    const auto params = read(k->param_size), x = read(k->state_size), w = read(k->input_size);
    if (!in) {
      std::cerr << "cart_rhs_driver: a line with too few numbers for " << n << " links\n";
      return 2;
    }
    std::vector<double> dxdt(static_cast<std::size_t>(k->state_size));
    k->rhs(x.data(), params.data(), w.data(), dxdt.data());
    for (std::size_t i = 0; i < dxdt.size(); ++i) std::printf("%s%.17g", i ? " " : "", dxdt[i]);
    std::printf("\n");
  }
  return 0;
}
