#include "scripting/core/script_source.hpp"

#include <array>

#include "persistence/state_document.hpp"

namespace mcemu::scripting {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// Calls fn(line_start, line) for every line (split at LF, the LF not included) until fn returns true.
template <typename Fn>
void for_each_line(std::string_view s, Fn&& fn) {
  std::size_t pos = 0;
  while (pos <= s.size()) {
    const std::size_t nl = s.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? s.size() : nl;
    if (fn(pos, s.substr(pos, end - pos))) return;
    if (nl == std::string_view::npos) return;
    pos = nl + 1;
  }
}

// Length of the longest prefix of `s` of at most `max` bytes that does not cut a UTF-8 sequence.
std::size_t utf8_cut(std::string_view s, std::size_t max) {
  if (s.size() <= max) return s.size();
  std::size_t n = max;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return n;
}

}  // namespace

std::string script_id(std::string_view source) {
  std::string id;
  bool found = false;
  for_each_line(source, [&](std::size_t, std::string_view line) {
    if (line.size() < 4 || line.substr(0, 3) != "#id" || (line[3] != ' ' && line[3] != '\t')) return false;
    std::string_view rest = line.substr(4);
    while (!rest.empty() && is_space(rest.front())) rest.remove_prefix(1);
    while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
    id = std::string(rest.substr(0, utf8_cut(rest, k_max_id_bytes)));
    found = true;
    return true;
  });
  if (!found || id.empty()) return std::string(k_empty_id);
  return id;
}

std::size_t private_offset(std::string_view source) {
  std::size_t at = std::string::npos;
  for_each_line(source, [&](std::size_t start, std::string_view line) {
    if (line.substr(0, 8) != "#private") return false;
    at = start;
    return true;
  });
  return at;
}

bool is_valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      n = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      n = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      n = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return false;
      const auto cc = static_cast<unsigned char>(s[i + k]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3F);
    }
    // overlong forms, surrogates and values above U+10FFFF are not UTF-8
    static constexpr std::array<std::uint32_t, 4> k_min{0, 0x80, 0x800, 0x10000};
    if (cp < k_min[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += n + 1;
  }
  return true;
}

ScriptSource::ScriptSource() : bytes_(k_placeholder), id_(k_empty_id), crc32_(persistence::crc32(k_placeholder)) {}

ScriptSource ScriptSource::from_bytes(std::string bytes) {
  ScriptSource s;
  s.placeholder_ = bytes == k_placeholder;
  s.id_ = script_id(bytes);
  s.crc32_ = persistence::crc32(bytes);
  s.private_at_ = private_offset(bytes);
  s.bytes_ = std::move(bytes);
  return s;
}

ScriptSource ScriptSource::from_record(const nlohmann::json& record) {
  if (!record.is_object()) return ScriptSource();
  const auto source = record.find("source");
  if (source == record.end() || !source->is_string()) return ScriptSource();
  const std::string encoding = record.value("encoding", std::string("utf-8"));
  std::string bytes = source->get<std::string>();
  if (encoding == "base64") {
    bool ok = false;
    bytes = base64_decode(bytes, ok);
    if (!ok) return ScriptSource();
  } else if (encoding != "utf-8") {
    return ScriptSource();
  }
  if (bytes.empty() || bytes.size() > k_max_script_bytes) return ScriptSource();
  return from_bytes(std::move(bytes));
}

std::string_view ScriptSource::visible() const {
  return std::string_view(bytes_).substr(0, private_at_ == std::string::npos ? bytes_.size() : private_at_);
}

nlohmann::json ScriptSource::record() const {
  if (placeholder_) return nullptr;
  const bool utf8 = is_valid_utf8(bytes_);
  return nlohmann::json{{"id", id_},
                        {"encoding", utf8 ? "utf-8" : "base64"},
                        {"source", utf8 ? bytes_ : base64_encode(bytes_)},
                        {"crc32", persistence::hex32(crc32_)}};
}

namespace {
constexpr std::string_view k_b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
}

std::string base64_encode(std::string_view in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                            static_cast<unsigned char>(in[i + 2]);
    for (int k = 3; k >= 0; --k) out += k_b64[(v >> (6 * k)) & 63];
  }
  if (i < in.size()) {
    std::uint32_t v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += k_b64[(v >> 18) & 63];
    out += k_b64[(v >> 12) & 63];
    out += i + 1 < in.size() ? k_b64[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string base64_decode(std::string_view in, bool& ok) {
  ok = false;
  if (in.size() % 4 != 0) return {};
  std::string out;
  std::uint32_t v = 0;
  int bits = 0;
  std::size_t pad = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '=') {
      if (i + 2 < in.size()) return {};
      ++pad;
      continue;
    }
    if (pad > 0) return {};
    const auto p = k_b64.find(c);
    if (p == std::string_view::npos) return {};
    v = (v << 6) | static_cast<std::uint32_t>(p);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((v >> bits) & 0xFF);
    }
  }
  ok = true;
  return out;
}

}  // namespace mcemu::scripting
