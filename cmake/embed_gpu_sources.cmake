# cmake -P script: writes OUTPUT, a C++ source holding the texts of FILES (paths separated
# by |) as string literals, found by their file stem through npend::gpu::embedded_source
# (runtime/src/gpu/gpu_sources.hpp). The GPU maps hand these texts to NVRTC at run time.
string(REPLACE "|" ";" FILES "${FILES}")
set(body "")
set(table "")
set(index 0)
foreach(path IN LISTS FILES)
  file(READ "${path}" text)
  get_filename_component(stem "${path}" NAME_WE)
  string(FIND "${text}" ")npend_gpu\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${path} holds the literal's delimiter )npend_gpu\"")
  endif()
  string(APPEND body "const char text_${index}[] = R\"npend_gpu(${text})npend_gpu\";\n")
  string(APPEND table "    {\"${stem}\", text_${index}},\n")
  math(EXPR index "${index} + 1")
endforeach()
file(WRITE "${OUTPUT}.tmp"
"// Written by cmake/embed_gpu_sources.cmake when the library is built: do not edit.
#include \"gpu/gpu_sources.hpp\"

#include <string_view>

namespace npend::gpu {
namespace {
${body}
struct entry {
  std::string_view name;
  const char* text;
};
const entry entries[] = {
${table}};
}  // namespace

std::string_view embedded_source(std::string_view name) {
  for (const entry& e : entries)
    if (e.name == name) return e.text;
  return {};
}

}  // namespace npend::gpu
")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
