// Our own C++ printer for the expression graphs: flat functions with only <cmath>, no
// allocation, shared subexpressions as named temporaries in a fixed order, `std::` maths,
// integer powers as products and 17 significant digits (a double round-trips).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "chain_functions.hpp"

namespace npend::gen {

/// Operation counts of one emitted function (what it executes per call).
struct operation_count {
  int add = 0, mul = 0, div = 0, neg = 0, trig = 0;
  int total() const { return add + mul + div + neg + trig; }
};

operation_count count_operations(const emitted_function& f);

/// The statements that compute `outputs` of graph `g`: every shared, trigonometric or long
/// subexpression as a `const double tK` temporary (in a fixed order), each line starting
/// with `indent`; and the text of each output (a temporary's name or a short expression).
/// `leaf` prints an input node.
struct emitted_statements {
  std::string text;
  std::vector<std::string> outputs;
};
emitted_statements emit_statements(const expr_graph& g, const std::vector<sx>& outputs,
                                   const std::function<std::string(const node&)>& leaf,
                                   const std::string& indent);

/// The line every generated file starts with.
std::string generated_banner(const std::string& command);

/// Header and source of chain_<n>.hpp / chain_<n>.cpp.
struct chain_sources {
  std::string header, source;
};
/// `latex` is the text of print_latex, embedded so that programs can show the equations;
/// `options` are further npend-gen options that made the functions ("--solver ldlt"), for
/// the banner's regeneration command.
/// A physical chain (kind link_kind::physical) is written as physical_<n>.hpp/.cpp with its
/// own table entry type, npend::physical_kernels.
chain_sources emit_chain(int links, const std::vector<emitted_function>& functions,
                         const std::string& latex, const std::string& options = {},
                         link_kind kind = link_kind::point_mass);

/// chain_index.hpp / chain_index.cpp: the tables of built link counts for the runtime, of the
/// point-mass chains and of the physical chains (the same counts).
chain_sources emit_index(const std::vector<int>& links);

/// File names of the sources for n links (chain_<n>, or physical_<n> for physical chains)
/// and of the index.
std::string chain_stem(int links, link_kind kind = link_kind::point_mass);
inline constexpr const char* index_stem = "chain_index";

/// A constant as the emitters print it (17 significant digits, or n.0).
std::string constant_literal(const GiNaC::numeric& value);
/// The nodes `outputs` depend on, each after its operands: the order the emitters print in.
std::vector<int> evaluation_order(const expr_graph& g, const std::vector<sx>& outputs);

}  // namespace npend::gen
