// Fuzz target: the multipart/form-data parser of the script upload (web.md §6.1; any client may POST
// /program.html). Input: the Content-Type value up to the first LF, then the body.
// Oracles: nothing throws or reads out of bounds; every part's content is a contiguous piece of the
// body; the parts, written back with the same boundary as python-requests writes them, parse again
// to the same names, filenames and contents (when no content contains the delimiter).
#include "web/api/multipart.hpp"

#include <string>
#include <string_view>

#include "tests/fuzz/drive_bundle.hpp"

using namespace mcemu;

namespace {

std::string in_quotes(std::string_view v) {
  std::string out = "\"";
  for (const char c : v) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const auto lf = input.find('\n');
  if (lf == std::string_view::npos) return 0;
  const auto boundary = web::api::multipart_boundary(input.substr(0, lf));
  if (!boundary) return 0;
  const std::string_view body = input.substr(lf + 1);
  const auto parts = web::api::parse_multipart(body, *boundary);
  if (!parts) return 0;
  std::string again;
  bool clean = true;
  for (const auto& p : *parts) {
    if (body.find(p.content) == std::string_view::npos) fuzz::fail("a part's content is not a piece of the body");
    if (p.content.find("\r\n--" + *boundary) != std::string::npos || p.content.rfind("--" + *boundary, 0) == 0 ||
        p.name.find_first_of("\r\n") != std::string::npos ||
        (p.filename && p.filename->find_first_of("\r\n") != std::string::npos)) {
      clean = false;
    }
    again += "--" + *boundary + "\r\nContent-Disposition: form-data; name=" + in_quotes(p.name);
    if (p.filename) again += "; filename=" + in_quotes(*p.filename);
    again += "\r\n\r\n" + p.content + "\r\n";
  }
  again += "--" + *boundary + "--\r\n";
  if (!clean || boundary->find('\r') != std::string::npos) return 0;
  const auto reparsed = web::api::parse_multipart(again, *boundary);
  if (!reparsed || reparsed->size() != parts->size()) fuzz::fail("written-back parts do not parse again");
  for (std::size_t i = 0; i < parts->size(); ++i) {
    const auto& x = (*parts)[i];
    const auto& y = (*reparsed)[i];
    if (x.name != y.name || x.filename != y.filename || x.content != y.content) fuzz::fail("a part changed");
  }
  return 0;
}
