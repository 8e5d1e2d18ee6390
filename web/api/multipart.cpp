#include "web/api/multipart.hpp"

#include <algorithm>

namespace mcemu::web::api {
namespace {

constexpr std::size_t k_max_boundary = 70;  // RFC 2046 §5.1.1

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == lower(y); });
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The parameters after the media type of a header value: `; name=value` or `; name="quoted"`
// (backslash escapes the next character inside quotes). Calls f(name, value) for each; false on a
// malformed list.
template <typename F>
bool for_each_parameter(std::string_view rest, F&& f) {
  std::size_t i = 0;
  while (i < rest.size()) {
    while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t')) ++i;
    if (i == rest.size()) break;
    if (rest[i] != ';') return false;
    ++i;
    while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t')) ++i;
    if (i == rest.size()) break;  // a trailing ';'
    const std::size_t name_start = i;
    while (i < rest.size() && rest[i] != '=' && rest[i] != ';') ++i;
    const std::string_view name = trim(rest.substr(name_start, i - name_start));
    if (i == rest.size() || rest[i] != '=' || name.empty()) return false;
    ++i;
    while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t')) ++i;
    std::string value;
    if (i < rest.size() && rest[i] == '"') {
      ++i;
      bool closed = false;
      while (i < rest.size()) {
        const char c = rest[i++];
        if (c == '"') {
          closed = true;
          break;
        }
        if (c == '\\' && i < rest.size()) {
          value += rest[i++];
        } else {
          value += c;
        }
      }
      if (!closed) return false;
    } else {
      const std::size_t start = i;
      while (i < rest.size() && rest[i] != ';') ++i;
      value = std::string(trim(rest.substr(start, i - start)));
    }
    f(name, std::move(value));
  }
  return true;
}

// The media type of a header value and the rest (its parameters).
std::pair<std::string_view, std::string_view> split_media(std::string_view value) {
  const auto semi = value.find(';');
  if (semi == std::string_view::npos) return {trim(value), {}};
  return {trim(value.substr(0, semi)), value.substr(semi)};
}

// One part: headers, an empty line, the content (the delimiter already removed).
std::optional<FormPart> parse_part(std::string_view raw) {
  FormPart part;
  std::string_view headers;
  std::string_view content;
  if (raw.substr(0, 2) == "\r\n") {  // no headers at all
    content = raw.substr(2);
  } else {
    const auto end = raw.find("\r\n\r\n");
    if (end == std::string_view::npos) return std::nullopt;
    headers = raw.substr(0, end);
    content = raw.substr(end + 4);
  }
  bool disposition = false;
  while (!headers.empty()) {
    const auto eol = headers.find("\r\n");
    const std::string_view line = headers.substr(0, eol);
    headers = eol == std::string_view::npos ? std::string_view() : headers.substr(eol + 2);
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return std::nullopt;
    const std::string_view name = trim(line.substr(0, colon));
    const std::string_view value = trim(line.substr(colon + 1));
    if (iequals(name, "content-disposition")) {
      const auto [type, params] = split_media(value);
      if (!iequals(type, "form-data")) return std::nullopt;
      bool has_name = false;
      const bool ok = for_each_parameter(params, [&](std::string_view key, std::string v) {
        if (iequals(key, "name")) {
          part.name = std::move(v);
          has_name = true;
        } else if (iequals(key, "filename")) {
          part.filename = std::move(v);
        }
      });
      if (!ok || !has_name) return std::nullopt;
      disposition = true;
    } else if (iequals(name, "content-type")) {
      part.content_type = std::string(value);
    }
  }
  if (!disposition) return std::nullopt;
  part.content = std::string(content);
  return part;
}

}  // namespace

std::optional<std::string> multipart_boundary(std::string_view content_type) {
  const auto [type, params] = split_media(content_type);
  if (!iequals(type, "multipart/form-data")) return std::nullopt;
  std::optional<std::string> boundary;
  const bool ok = for_each_parameter(params, [&](std::string_view key, std::string v) {
    if (iequals(key, "boundary") && !boundary) boundary = std::move(v);
  });
  if (!ok || !boundary || boundary->empty() || boundary->size() > k_max_boundary) return std::nullopt;
  return boundary;
}

std::optional<std::vector<FormPart>> parse_multipart(std::string_view body, std::string_view boundary) {
  const std::string dash = "--" + std::string(boundary);
  const std::string delimiter = "\r\n" + dash;
  // The first delimiter line: at the very start, or after the preamble's CRLF.
  std::size_t pos = 0;
  if (body.substr(0, dash.size()) == dash) {
    pos = dash.size();
  } else {
    const auto first = body.find(delimiter);
    if (first == std::string_view::npos) return std::nullopt;
    pos = first + delimiter.size();
  }
  std::vector<FormPart> parts;
  for (;;) {
    if (body.substr(pos, 2) == "--") return parts;  // close delimiter; the epilogue is ignored
    // transport padding, then the CRLF that ends the delimiter line
    while (pos < body.size() && (body[pos] == ' ' || body[pos] == '\t')) ++pos;
    if (body.substr(pos, 2) != "\r\n") return std::nullopt;
    pos += 2;
    const auto next = body.find(delimiter, pos);
    if (next == std::string_view::npos) return std::nullopt;
    auto part = parse_part(body.substr(pos, next - pos));
    if (!part) return std::nullopt;
    parts.push_back(std::move(*part));
    pos = next + delimiter.size();
  }
}

}  // namespace mcemu::web::api
