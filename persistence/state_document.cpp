#include "persistence/state_document.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "drive/od/hex.hpp"

namespace mcemu::persistence {

using nlohmann::json;

Group group_of(const od::EntryInfo& e) {
  if (e.index == 0x5006 && e.sub == 5) return Group::nvm;
  const bool persistent = e.cls == od::EntryClass::param || e.cls == od::EntryClass::comm;
  if (!persistent) return Group::none;
  if (e.index == 0x3300 || e.index == 0x3400) return Group::motor;
  if ((e.index == 0x3404 && e.sub == 3) || e.index == 0x5007 || e.index == 0x5008) return Group::network;
  return Group::parameters;
}

Image snapshot(const od::ObjectDictionary& od) {
  Image img;
  od.for_each([&](const od::EntryInfo& e, const od::Value& v) {
    if (group_of(e) != Group::none) img.objects.push_back({e.index, e.sub, v});
  });
  img.autostart = od.find(0x3500, 4) && od.number(0x3500, 4) != 0;
  return img;
}

std::string object_key(std::uint16_t index, std::uint8_t sub) {
  std::array<char, 8> buf{};
  std::snprintf(buf.data(), buf.size(), "%04X.%02X", index, sub);
  return buf.data();
}

std::optional<std::pair<std::uint16_t, std::uint8_t>> parse_object_key(std::string_view key) {
  if (key.size() != 7 || key[4] != '.') return std::nullopt;
  const auto index = od::parse_hex(key.substr(0, 4), 0xFFFF);
  const auto sub = od::parse_hex(key.substr(5, 2), 0xFF);
  if (!index || !sub) return std::nullopt;
  return std::pair{static_cast<std::uint16_t>(*index), static_cast<std::uint8_t>(*sub)};
}

std::uint32_t crc32(std::string_view bytes) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFU;
  for (char ch : bytes) c = table[(c ^ static_cast<unsigned char>(ch)) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
}

std::string hex32(std::uint32_t v) {
  std::array<char, 12> buf{};
  std::snprintf(buf.data(), buf.size(), "0x%08x", v);
  return buf.data();
}

namespace {

// Well-formed UTF-8 (Unicode 15 table 3-7): what nlohmann-json's strict dump() accepts.
bool is_utf8(std::string_view s) {
  std::size_t i = 0;
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  while (i < s.size()) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t n = 0;
    unsigned char lo = 0x80;
    unsigned char hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) {
      n = 1;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2;
      if (c == 0xE0) lo = 0xA0;  // no overlong forms
      if (c == 0xED) hi = 0x9F;  // no surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3;
      if (c == 0xF0) lo = 0x90;  // no overlong forms
      if (c == 0xF4) hi = 0x8F;  // nothing above U+10FFFF
    } else {
      return false;
    }
    if (i + n >= s.size()) return false;  // cut short
    if (byte(i + 1) < lo || byte(i + 1) > hi) return false;
    for (std::size_t k = 2; k <= n; ++k) {
      if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return false;
    }
    i += n + 1;
  }
  return true;
}

// The state file's text written straight from the image, byte for byte what nlohmann-json's dump()
// of the document would be (keys sorted, `pretty`: dump(2); else dump()), without building the
// document: a Store or Restore writes the whole dictionary, and the document was most of its cost
// (a node and a key string per object). tests/persistence/state_document_test.cpp keeps the
// document as the reference.
class Writer {
 public:
  Writer(std::string& out, bool pretty) : out_(out), pretty_(pretty) {}

  void open() {
    out_.push_back('{');
    first_ = true;
    ++depth_;
  }
  void close() {
    --depth_;
    if (pretty_ && !first_) newline();
    out_.push_back('}');
    first_ = false;
  }
  void key(std::string_view k) {
    if (!first_) out_.push_back(',');
    if (pretty_) newline();
    string(k);
    out_.append(pretty_ ? ": " : ":");
    first_ = false;
  }
  void number(std::int64_t n) { out_.append(std::to_string(n)); }
  void boolean(bool b) { out_.append(b ? "true" : "false"); }
  // As dump() escapes (ensure_ascii off): `"`, `\`, the short escapes, other controls as \u00xx.
  void string(std::string_view s) {
    if (!is_utf8(s)) {
      out_.append(json(std::string(s)).dump());  // throws type_error 316, as the document's dump did
      return;
    }
    out_.push_back('"');
    for (const char ch : s) {
      const auto c = static_cast<unsigned char>(ch);
      switch (c) {
        case '"': out_.append("\\\""); break;
        case '\\': out_.append("\\\\"); break;
        case '\b': out_.append("\\b"); break;
        case '\f': out_.append("\\f"); break;
        case '\n': out_.append("\\n"); break;
        case '\r': out_.append("\\r"); break;
        case '\t': out_.append("\\t"); break;
        default:
          if (c < 0x20) {
            std::array<char, 8> buf{};
            std::snprintf(buf.data(), buf.size(), "\\u%04x", c);
            out_.append(buf.data());
          } else {
            out_.push_back(ch);
          }
      }
    }
    out_.push_back('"');
  }
  // An opaque value (the script object): its own dump, indented to where it stands.
  void value(const json& j) {
    if (!pretty_) {
      out_.append(j.dump());
      return;
    }
    const std::string text = j.dump(2);  // a dump holds no raw line end inside a string
    for (const char ch : text) {
      out_.push_back(ch);
      if (ch == '\n') out_.append(2 * depth_, ' ');
    }
  }

 private:
  void newline() {
    out_.push_back('\n');
    out_.append(2 * depth_, ' ');
  }

  std::string& out_;
  bool pretty_;
  bool first_ = true;
  std::size_t depth_ = 0;
};

// The objects in key order ("IIII.SS", upper-case hex of fixed width: the numeric order), the last
// of equal keys kept, as assigning them to a JSON object in image order would.
std::vector<const od::StoredValue*> key_order(const Image& image) {
  std::vector<const od::StoredValue*> v;
  v.reserve(image.objects.size());
  for (const auto& sv : image.objects) v.push_back(&sv);
  const auto key = [](const od::StoredValue* p) { return (std::uint32_t{p->index} << 8) | p->sub; };
  std::stable_sort(v.begin(), v.end(), [&](const auto* a, const auto* b) { return key(a) < key(b); });
  std::vector<const od::StoredValue*> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i + 1 < v.size() && key(v[i + 1]) == key(v[i])) continue;
    out.push_back(v[i]);
  }
  return out;
}

void write_payload(Writer& w, const Image& image, const std::vector<const od::StoredValue*>& objects) {
  w.open();
  w.key("home_offset_inc");
  w.number(image.home_offset_inc);
  w.key("objects");
  w.open();
  for (const auto* sv : objects) {
    w.key(object_key(sv->index, sv->sub));
    if (const auto* n = std::get_if<std::int64_t>(&sv->value)) {
      w.number(*n);
    } else {
      w.string(std::get<std::string>(sv->value));
    }
  }
  w.close();
  w.key("program");
  w.open();
  w.key("autostart");
  w.boolean(image.autostart);
  w.key("script");
  w.value(image.script);
  w.close();
  w.close();
}

}  // namespace

std::string serialize(const Image& image, std::string_view model, std::string_view mcemu_version,
                      std::string_view written_utc) {
  const auto objects = key_order(image);
  std::string compact;  // what payload_crc32 is the CRC of
  compact.reserve(objects.size() * 20 + 128);
  Writer c(compact, false);
  write_payload(c, image, objects);

  std::string out;
  out.reserve(compact.size() + objects.size() * 8 + 512);
  Writer w(out, true);
  w.open();
  w.key("format");
  w.string(k_format);
  w.key("format_version");
  w.number(k_format_version);
  w.key("mcemu_version");
  w.string(mcemu_version);
  w.key("model");
  w.string(model);
  w.key("payload");
  write_payload(w, image, objects);
  w.key("payload_crc32");
  w.string(hex32(crc32(compact)));
  w.key("written_utc");
  w.string(written_utc);
  w.close();
  out.push_back('\n');
  return out;
}

std::variant<ParsedFile, ParseFailure> parse(std::string_view text, std::string_view running_model,
                                             const od::ObjectDictionary& od) {
  // A real file is far below both limits (the whole dictionary and a 64 KiB script, base64: < 1 MiB);
  // beyond them it is not a state file of ours, and it is not held in memory as one.
  if (text.size() > k_max_state_file_bytes) return ParseFailure{"larger than 16 MiB"};
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded()) return ParseFailure{"not valid JSON"};
  if (!doc.is_object()) return ParseFailure{"not a JSON object"};
  for (const char* member : {"format", "format_version", "model", "payload", "payload_crc32"}) {
    if (!doc.contains(member)) return ParseFailure{std::string("missing member \"") + member + "\""};
  }
  if (doc["format"] != k_format) return ParseFailure{"wrong format"};
  if (!doc["format_version"].is_number_integer()) return ParseFailure{"format_version is not an integer"};
  if (doc["format_version"].get<std::int64_t>() > k_format_version) {
    return ParseFailure{"format_version " + doc["format_version"].dump() + " is newer than supported"};
  }
  if (!doc["model"].is_string()) return ParseFailure{"model is not a string"};
  const auto model = doc["model"].get<std::string>();
  if (model != running_model)
    return ParseFailure{"stored for model " + model + ", running as " + std::string(running_model)};
  const json& payload = doc["payload"];
  if (!payload.is_object() || !doc["payload_crc32"].is_string()) return ParseFailure{"malformed payload"};
  if (hex32(crc32(payload.dump())) != doc["payload_crc32"].get<std::string>()) {
    return ParseFailure{"payload_crc32 mismatch"};
  }
  if (!payload.contains("objects") || !payload["objects"].is_object()) return ParseFailure{"missing payload.objects"};
  if (payload["objects"].size() > k_max_state_objects) return ParseFailure{"more than 65536 objects"};

  ParsedFile out;
  for (const auto& [key, value] : payload["objects"].items()) {
    const auto k = parse_object_key(key);
    const od::EntryInfo* info = k ? od.info(k->first, k->second) : nullptr;
    if (!info || group_of(*info) == Group::none) {
      out.bad_keys.push_back(key);
      continue;
    }
    od::Value v;
    if (value.is_number_integer()) {
      v = value.get<std::int64_t>();
    } else if (value.is_string()) {
      v = value.get<std::string>();
    } else {
      out.bad_keys.push_back(key);
      continue;
    }
    auto converted = od::convert_for_write(*info, v);
    if (!converted || (std::holds_alternative<std::int64_t>(v) && std::get<std::int64_t>(v) < 0 &&
                       info->type == od::DataType::unsigned32)) {
      out.bad_keys.push_back(key);
      continue;
    }
    out.image.objects.push_back({k->first, k->second, std::move(*converted)});
  }
  if (payload.contains("home_offset_inc") && payload["home_offset_inc"].is_number_integer()) {
    out.image.home_offset_inc = payload["home_offset_inc"].get<std::int64_t>();
  }
  if (payload.contains("program") && payload["program"].is_object()) {
    const json& p = payload["program"];
    if (p.contains("autostart") && p["autostart"].is_boolean()) out.image.autostart = p["autostart"].get<bool>();
    if (p.contains("script") && p["script"].is_object()) out.image.script = p["script"];
  }
  return out;
}

std::string serialize_plant(std::string_view model, std::int64_t raw_position_inc) {
  const json doc{
      {"format", k_plant_format}, {"format_version", 1}, {"model", model}, {"raw_position_inc", raw_position_inc}};
  return doc.dump(2) + "\n";
}

std::optional<std::int64_t> parse_plant(std::string_view text, std::string_view running_model) {
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return std::nullopt;
  // json::value() throws when the member is there with another type ("format": 1): compare strings only
  const auto is_string_equal = [&doc](const char* key, std::string_view want) {
    const auto it = doc.find(key);
    return it != doc.end() && it->is_string() && it->get_ref<const std::string&>() == want;
  };
  if (!is_string_equal("format", k_plant_format) || !is_string_equal("model", running_model)) return std::nullopt;
  if (!doc.contains("raw_position_inc") || !doc["raw_position_inc"].is_number_integer()) return std::nullopt;
  return doc["raw_position_inc"].get<std::int64_t>();
}

}  // namespace mcemu::persistence
