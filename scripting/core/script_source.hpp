// The loaded MovingCap CODE script as a value (scripting.md §2): its bytes, the `#id` and
// `#private` tags, length and CRC-32 (3500h.01/.05/.06), the placeholder of §2.3 and the script
// record of the program group that Store Permanently keeps (persistence.md §2, §9).
//
// Pure: no I/O. The bytes are kept unchanged (line endings and encoding as uploaded).
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace mcemu::scripting {

inline constexpr std::size_t k_max_script_bytes = 65536;  // web.md §6.1
inline constexpr std::size_t k_max_id_bytes = 64;         // §2.2
inline constexpr std::string_view k_placeholder = "#id (empty)\r\n";
inline constexpr std::string_view k_empty_id = "(empty)";

// The id of §2.2: the first line starting in column 1 with "#id" and a space or tab; the rest of
// the line trimmed of white space (CR too), cut to 64 bytes at a UTF-8 character boundary. No such
// line, or nothing after the tag: "(empty)" [choice: an empty id would leave 3500h.01 blank].
std::string script_id(std::string_view source);

// Byte offset of the first line that starts with "#private", or npos (§2.2).
std::size_t private_offset(std::string_view source);

bool is_valid_utf8(std::string_view bytes);

class ScriptSource {
 public:
  ScriptSource();  // the placeholder
  static ScriptSource placeholder() { return ScriptSource(); }
  // Any bytes (the caller checks the size limits of the upload).
  static ScriptSource from_bytes(std::string bytes);
  // The program group's record (persistence.md §9): null or anything malformed → placeholder.
  static ScriptSource from_record(const nlohmann::json& record);

  const std::string& bytes() const { return bytes_; }
  const std::string& id() const { return id_; }
  std::uint32_t length() const { return static_cast<std::uint32_t>(bytes_.size()); }
  std::uint32_t crc32() const { return crc32_; }
  bool is_placeholder() const { return placeholder_; }
  bool has_private() const { return private_at_ != std::string::npos; }
  // The source up to, not including, the first `#private` line (Script Viewer, GET /api/v1/script).
  std::string_view visible() const;
  // persistence.md §9 `program.script`: null for the placeholder, else
  // {"id", "encoding": "utf-8"|"base64", "source", "crc32": "0x…"}.
  nlohmann::json record() const;

 private:
  std::string bytes_;
  std::string id_;
  std::uint32_t crc32_ = 0;
  std::size_t private_at_ = std::string::npos;
  bool placeholder_ = true;
};

std::string base64_encode(std::string_view bytes);
// nullopt-free: invalid characters make the result empty and `ok` false.
std::string base64_decode(std::string_view text, bool& ok);

}  // namespace mcemu::scripting
