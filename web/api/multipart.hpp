// multipart/form-data request bodies (RFC 7578, RFC 2046 §5.1.1) as the script upload of web.md
// §6.1 needs them: the boundary of a Content-Type value, and the parts of a body with their
// Content-Disposition name, filename and Content-Type. A part's content is the bytes between the
// empty line that ends its headers and the CRLF before the next delimiter line, unchanged.
// PURE; never throws; malformed input is nullopt.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::web::api {

struct FormPart {
  std::string name;                     // Content-Disposition name (exact bytes)
  std::optional<std::string> filename;  // Content-Disposition filename, if given
  std::string content_type;             // the part's Content-Type ("" if none)
  std::string content;
};

// The boundary of a `multipart/form-data` Content-Type (media type compared case-insensitively, the
// parameter name too; the value may be quoted; 1 … 70 characters). nullopt for any other media type
// or a missing or invalid boundary.
std::optional<std::string> multipart_boundary(std::string_view content_type);

// The parts of `body` (the preamble before the first delimiter and the epilogue after the close
// delimiter are ignored). nullopt when there is no delimiter, a part has no header end, a part is
// not closed by a delimiter, or a part has no form-data Content-Disposition with a name.
std::optional<std::vector<FormPart>> parse_multipart(std::string_view body, std::string_view boundary);

}  // namespace mcemu::web::api
