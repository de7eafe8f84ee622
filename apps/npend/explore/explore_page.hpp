// The files of npend explore's page (page/), compiled into the binary at build time
// (embed_page.cmake), so that the page works offline and from an installed npend.
#pragma once

#include <span>
#include <string_view>

namespace npend::app {

struct page_file {
  std::string_view route;    ///< "/", "/explore.js", ...
  std::string_view type;     ///< its Content-Type
  std::string_view content;  ///< the file, byte for byte
};

std::span<const page_file> page_files();

}  // namespace npend::app
