// The state directory at power on (persistence.md §8, §9, §11): stale temp files, loading and
// validating drive-N.json, moving a corrupt or foreign file aside, the plant-state file. Logs the
// lines the spec prescribes (one line per situation).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "drive/od/dictionary.hpp"
#include "persistence/state_document.hpp"

namespace mcemu::persistence {

class StateDir {
 public:
  explicit StateDir(std::filesystem::path dir, int drive_number = 1);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path state_file() const;
  std::filesystem::path plant_file() const;

  // Deletes a leftover drive-N.json.tmp (one info line).
  void remove_stale_temp() const;
  // Reads and validates the state file. A corrupt/foreign file is moved aside (one warning);
  // unknown keys and values of the wrong type are returned in bad_keys. `utc_stamp` =
  // "20260115T101502Z".
  std::optional<ParsedFile> load(std::string_view model, const od::ObjectDictionary& od,
                                 const std::string& utc_stamp) const;
  // The one warning of §11 for stored values that were not applied (nothing if `keys` is empty).
  void warn_ignored(const std::vector<std::string>& keys) const;
  std::optional<std::int64_t> load_plant(std::string_view model) const;

 private:
  std::filesystem::path dir_;
  int drive_;
};

}  // namespace mcemu::persistence
