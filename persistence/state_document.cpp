#include "persistence/state_document.hpp"

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

json payload_json(const Image& image) {
  json objects = json::object();
  for (const auto& sv : image.objects) {
    const auto key = object_key(sv.index, sv.sub);
    if (std::holds_alternative<std::int64_t>(sv.value)) {
      objects[key] = std::get<std::int64_t>(sv.value);
    } else {
      objects[key] = std::get<std::string>(sv.value);
    }
  }
  return json{{"objects", objects},
              {"home_offset_inc", image.home_offset_inc},
              {"program", json{{"autostart", image.autostart}, {"script", image.script}}}};
}

std::string serialize(const Image& image, std::string_view model, std::string_view mcemu_version,
                      std::string_view written_utc) {
  const json payload = payload_json(image);
  const json doc{{"format", k_format},
                 {"format_version", k_format_version},
                 {"model", model},
                 {"mcemu_version", mcemu_version},
                 {"written_utc", written_utc},
                 {"payload", payload},
                 {"payload_crc32", hex32(crc32(payload.dump()))}};
  return doc.dump(2) + "\n";
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
