#include "chain_implementation.hpp"

#include <chain_index.hpp>
#include <chain_loop.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "reference/chain_recursion.hpp"
#include "reference/dense_chain.hpp"
#include "reference/physical_recursion.hpp"
#include "sympy_kernels.hpp"

namespace npend::bench {

namespace {

// The generated kernels and SymPy's: plain functions of (x, params, out).
template <class kernels>
class kernel_implementation final : public chain_implementation {
 public:
  kernel_implementation(const kernels& k, std::vector<double> packed)
      : m_kernels(k), m_params(std::move(packed)) {}
  void rhs(const double* x, double* dxdt) override { m_kernels.rhs(x, m_params.data(), dxdt); }
  bool has_jacobian() const override { return true; }
  void jacobian(const double* x, double* jac) override {
    m_kernels.jacobian(x, m_params.data(), jac);
  }

 private:
  const kernels& m_kernels;
  std::vector<double> m_params;  ///< [m_1..m_n, l_1..l_n, g]
};

// The physical kernels with their time-dependent inputs (pivot acceleration, torques) zero.
class physical_implementation final : public chain_implementation {
 public:
  physical_implementation(const physical_kernels& k, const chain_parameters& p)
      : m_kernels(k),
        m_params(p.physical_packed()),
        m_inputs(static_cast<std::size_t>(chain_layout::input_size(p.links())), 0.0) {}
  void rhs(const double* x, double* dxdt) override {
    m_kernels.rhs(x, m_params.data(), m_inputs.data(), dxdt);
  }
  bool has_jacobian() const override { return true; }
  void jacobian(const double* x, double* jac) override {
    m_kernels.jacobian(x, m_params.data(), m_inputs.data(), jac);
  }

 private:
  const physical_kernels& m_kernels;
  std::vector<double> m_params, m_inputs;
};

// The loop kernels (any n), with their workspace.
class loop_implementation final : public chain_implementation {
 public:
  explicit loop_implementation(const chain_parameters& p)
      : m_links(p.links()),
        m_params(p.packed()),
        m_work(generated::chain_loop::jacobian_workspace_size(p.links())) {}
  void rhs(const double* x, double* dxdt) override {
    generated::chain_loop::rhs(m_links, x, m_params.data(), dxdt, m_work.data());
  }
  bool has_jacobian() const override { return true; }
  void jacobian(const double* x, double* jac) override {
    generated::chain_loop::jacobian(m_links, x, m_params.data(), jac, m_work.data());
  }

 private:
  int m_links;
  std::vector<double> m_params, m_work;
};

class recursion_implementation final : public chain_implementation {
 public:
  explicit recursion_implementation(const chain_parameters& p)
      : m_recursion(p.masses, p.lengths, p.g) {}
  void rhs(const double* x, double* dxdt) override { m_recursion.rhs(x, dxdt); }
  bool has_jacobian() const override { return false; }
  void jacobian(const double*, double*) override {
    throw std::logic_error("the recursion peer has no Jacobian");
  }

 private:
  reference::chain_recursion m_recursion;
};

// The physical chain's hand-written recursion, with the parameters the physical kernels get
// (c = l, J = 0 and no springs or damping unless the chain sets them).
class physical_recursion_implementation final : public chain_implementation {
 public:
  explicit physical_recursion_implementation(const chain_parameters& p)
      : m_recursion(make(p.physical_packed(), p.links())) {}
  void rhs(const double* x, double* dxdt) override { m_recursion.rhs(x, dxdt); }
  bool has_jacobian() const override { return false; }
  void jacobian(const double*, double*) override {
    throw std::logic_error("the physical recursion peer has no Jacobian");
  }

 private:
  static reference::physical_recursion make(const std::vector<double>& packed, int n) {
    const auto block = [&](int first) {
      return std::vector<double>(packed.begin() + first, packed.begin() + first + n);
    };
    return {block(0),
            block(n),
            packed[static_cast<std::size_t>(2 * n)],
            block(chain_layout::com_index(n, 0)),
            block(chain_layout::inertia_index(n, 0)),
            block(chain_layout::stiffness_index(n, 0)),
            block(chain_layout::rest_angle_index(n, 0)),
            block(chain_layout::damping_index(n, 0))};
  }
  reference::physical_recursion m_recursion;
};

class eigen_implementation final : public chain_implementation {
 public:
  explicit eigen_implementation(const chain_parameters& p)
      : m_chain(p.masses, p.lengths, p.g), m_workspace(p.links()) {}
  void rhs(const double* x, double* dxdt) override { m_chain.rhs(x, dxdt, m_workspace); }
  bool has_jacobian() const override { return true; }
  void jacobian(const double* x, double* jac) override { m_chain.jacobian(x, jac, m_workspace); }

 private:
  reference::dense_chain m_chain;
  reference::dense_chain::workspace m_workspace;
};

}  // namespace

std::unique_ptr<chain_implementation> make_implementation(std::string_view name,
                                                          const chain_parameters& params) {
  params.validate();
  const int n = params.links();
  if (name == "generated") {
    const npend::chain_kernels* kernels = generated::find_chain(n);
    if (kernels == nullptr) return nullptr;
    return std::make_unique<kernel_implementation<npend::chain_kernels>>(*kernels, params.packed());
  }
  if (name == "physical") {
    const npend::physical_kernels* kernels = generated::find_physical(n);
    if (kernels == nullptr) return nullptr;
    return std::make_unique<physical_implementation>(*kernels, params);
  }
  if (name == "recursion") return std::make_unique<recursion_implementation>(params);
  if (name == "loop") return std::make_unique<loop_implementation>(params);
  if (name == "eigen") return std::make_unique<eigen_implementation>(params);
  if (name == "physical-recursion")
    return std::make_unique<physical_recursion_implementation>(params);
  if (name == "sympy") {
    const sympy_kernels* kernels = find_sympy_chain(n);
    if (kernels == nullptr) return nullptr;
    return std::make_unique<kernel_implementation<sympy_kernels>>(*kernels, params.packed());
  }
  throw std::invalid_argument(
      "make_implementation: unknown implementation '" + std::string(name) +
      "' (expected generated, loop, recursion, eigen, sympy, physical or physical-recursion)");
}

}  // namespace npend::bench
