// The files of the web UI (web/ui/), compiled into the binary (web.md §1.5): nothing is read from
// disk at run time. The table is generated at build time by embed_assets.cmake; its paths are URL
// paths ("/index.html", "/static/mcemu.css"), sorted. PURE, immutable, safe from any thread.
#pragma once

#include <span>
#include <string_view>

namespace mcemu::web::assets {

struct Asset {
  std::string_view path;   // "/static/mcemu.css"
  std::string_view mime;   // "text/css; charset=utf-8"
  std::string_view etag;   // strong ETag with its quotes: "\"3f2a…\"" (content hash)
  std::string_view bytes;  // the file's content
};

// The asset at exactly `path` (no query, no "/" → "/index.html" mapping: see static_files.hpp).
const Asset* find(std::string_view path);
// Every asset, sorted by path.
std::span<const Asset> all();

}  // namespace mcemu::web::assets
