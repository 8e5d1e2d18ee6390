// Fuzz target: the state file loader (persistence.md §9, §11) as start-up uses it: parse() of
// drive-1.json against the running model's dictionary, then the bulk load of the values it
// accepted; and parse_plant() of drive-1.plant.json. Input: the first byte picks the model, the
// file, and whether the harness first re-stamps payload_crc32 (else almost every mutation of the
// payload would stop at the CRC check and the object validation would never be reached); the rest
// is the file's text.
// Oracles: parse() never throws (corrupt or foreign is a ParseFailure, moved aside by the caller);
// a value the bulk load refuses is reported and its entry keeps the factory value (§11); the
// dictionary is never corrupted; an accepted image written back with serialize() parses again to
// the same values.
#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "persistence/state_document.hpp"
#include "tests/fuzz/drive_bundle.hpp"

using namespace mcemu;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static constexpr std::array<const char*, 4> k_models = {"MC349", "MCFLAT", "MC636", "MCN23"};
  // parse() does not change the dictionary: one per model serves every input's parse
  static const auto dictionaries = [] {
    std::array<std::unique_ptr<od::ObjectDictionary>, k_models.size()> d;
    for (std::size_t i = 0; i < d.size(); ++i)
      d[i] = std::make_unique<od::ObjectDictionary>(*model::find_preset(k_models[i]));
    return d;
  }();
  const std::size_t m = data[0] % k_models.size();
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (data[0] & 0x80) {
    (void)persistence::parse_plant(text, k_models[m]);
    return 0;
  }
  std::string stamped;
  std::string_view file_text = text;
  if (data[0] & 0x40) {
    auto doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_object() && doc.contains("payload")) {
      doc["payload_crc32"] = persistence::hex32(persistence::crc32(doc["payload"].dump()));
      stamped = doc.dump();
      file_text = stamped;
    }
  }
  const auto parsed = persistence::parse(file_text, k_models[m], *dictionaries[m]);
  const auto* file = std::get_if<persistence::ParsedFile>(&parsed);
  if (!file) return 0;

  // persistence.md §11: a value out of range keeps the factory value and is reported (the caller
  // warns); parse() checks the type range only, the bulk load the limits of §5 as well.
  od::ObjectDictionary od(*model::find_preset(k_models[m]));
  for (const auto& issue : od.load_values(file->image.objects)) {
    const auto h = od.find(issue.index, issue.sub);
    if (!h || !(od.value(*h) == od.info(*h).factory)) fuzz::fail("a refused stored value changed its entry");
  }
  fuzz::check_dictionary(od);

  const std::string again = persistence::serialize(file->image, k_models[m], "fuzz", "2026-01-15T10:15:02Z");
  const auto reparsed = persistence::parse(again, k_models[m], od);
  const auto* second = std::get_if<persistence::ParsedFile>(&reparsed);
  if (!second) fuzz::fail("an accepted image, written back, does not parse");
  if (second->image.objects.size() != file->image.objects.size()) fuzz::fail("write-back changed the objects");
  for (std::size_t i = 0; i < file->image.objects.size(); ++i) {
    const auto& x = file->image.objects[i];
    const auto& y = second->image.objects[i];
    if (x.index != y.index || x.sub != y.sub || x.value != y.value) fuzz::fail("write-back changed a value");
  }
  return 0;
}
