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
/// `leaf` prints an input node; `math` qualifies sin and cos (`std::` for C++, empty for the
/// GPU's device functions, which call CUDA's unqualified ones).
struct emitted_statements {
  std::string text;
  std::vector<std::string> outputs;
};
emitted_statements emit_statements(const expr_graph& g, const std::vector<sx>& outputs,
                                   const std::function<std::string(const node&)>& leaf,
                                   const std::string& indent, const std::string& math = "std::");

/// The lines every generated file starts with: what made it and how to remake it, and that
/// it is covered by the output exception of LICENSE-EXCEPTION.md.
std::string generated_banner(const std::string& command);

/// The npend-gen command that writes a chain's files, for their banners: `options` as for
/// emit_chain.
std::string chain_command(int links, const std::string& options, link_kind kind);

/// The definition of `f` for `links` links as <stem>_<n>.cpp has it (signature, then the
/// body of emit_statements), with `math` qualifying sin and cos.
std::string function_definition(int links, const emitted_function& f, link_kind kind,
                                const std::string& math = "std::");

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

/// A model whose kernels npend-gen writes, one per link count: a new model is one row of
/// emitted_models, its kinematics (chain_model.hpp) and one line in cmake/npend_codegen.cmake.
struct emitted_model {
  link_kind kind;
  const char* stem;   ///< its files are <stem>_<n>.hpp/.cpp, namespace npend::generated::<stem>_<n>
  const char* table;  ///< the kernel table type of <npend/chain_kernels.hpp> it fills
  const char* lookup;  ///< the index's function that finds a link count's table
  const char* array;   ///< the index's array of the tables
  const char* doc;     ///< the lookup's doc comment
};

/// The models with emitted kernels, in the order the index lists them.
const std::vector<emitted_model>& emitted_models();
/// The row of `kind`; throws std::invalid_argument for a model without emitted kernels.
const emitted_model& emitted_model_of(link_kind kind);

/// A generated index: for each table its lookup `const type* lookup(int links)` over the
/// kernels <stem>_<n>::kernels of the given link counts, and optionally built_links().
struct lookup_index {
  struct table {
    std::string type, lookup, doc, array, stem;
  };
  std::string stem;     ///< the index's file stem
  std::string intro;    ///< the header's comment lines, each ending in a newline
  std::string include;  ///< the header that declares the table types
  std::vector<table> tables;
  bool built_links = false;
  /// An inline namespace around the declarations and definitions (empty: none), such as the
  /// batch kernels' ISA namespace.
  std::string inline_namespace;
};
chain_sources emit_lookup_index(const lookup_index& index, const std::vector<int>& links);

/// chain_index.hpp / chain_index.cpp: the tables of built link counts for the runtime, one
/// lookup per emitted model (the same counts), and built_links().
chain_sources emit_index(const std::vector<int>& links);

/// File names of the sources for n links (<stem>_<n> of the model's emitted_models row).
std::string chain_stem(int links, link_kind kind = link_kind::point_mass);
inline constexpr const char* index_stem = "chain_index";

/// The C++ text of input node `in` of an n-link chain of `kind` in a function with `layout`:
/// "x[3]", "params[5]", "inputs[0]" (the positions of chain_layout or cart_layout).
std::string input_text(argument_layout layout, int n, const node& in, link_kind kind);

/// A constant as the emitters print it (17 significant digits, or n.0).
std::string constant_literal(const GiNaC::numeric& value);
/// The nodes `outputs` depend on, each after its operands: the order the emitters print in.
std::vector<int> evaluation_order(const expr_graph& g, const std::vector<sx>& outputs);

}  // namespace npend::gen
