#include "persistence/state_dir.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>

#include "persistence/atomic_file.hpp"

namespace mcemu::persistence {

namespace fs = std::filesystem;

StateDir::StateDir(fs::path dir, int drive_number) : dir_(std::move(dir)), drive_(drive_number) {}

fs::path StateDir::state_file() const { return dir_ / ("drive-" + std::to_string(drive_) + ".json"); }
fs::path StateDir::plant_file() const { return dir_ / ("drive-" + std::to_string(drive_) + ".plant.json"); }

void StateDir::remove_stale_temp() const {
  for (fs::path tmp : {state_file(), plant_file()}) {
    tmp += ".tmp";
    std::error_code ec;
    if (fs::exists(tmp, ec) && fs::remove(tmp, ec)) {
      spdlog::info("removed {} left over from an interrupted store", tmp.string());
    }
  }
}

std::optional<ParsedFile> StateDir::load(std::string_view model, const od::ObjectDictionary& od,
                                         const std::string& utc_stamp) const {
  std::string error;
  const fs::path file = state_file();
  const auto text = read_file(file, error);
  if (!text) {
    if (!error.empty()) {
      spdlog::error("{}; using factory defaults (stores will fail)", error);
    } else {
      spdlog::info("no stored parameters in {} ({}); using factory defaults", dir_.string(), file.filename().string());
    }
    return std::nullopt;
  }
  auto parsed = parse(*text, model, od);
  if (auto* failure = std::get_if<ParseFailure>(&parsed)) {
    fs::path aside = file;
    aside += ".corrupt-" + utc_stamp;
    for (int n = 2; fs::exists(aside); ++n) {
      aside = file;
      aside += ".corrupt-" + utc_stamp + "-" + std::to_string(n);
    }
    std::error_code ec;
    fs::rename(file, aside, ec);
    if (ec) {
      spdlog::warn("state file {} is corrupt ({}); could not move it aside ({}); starting with factory defaults",
                   file.string(), failure->reason, ec.message());
    } else {
      spdlog::warn("state file {} is corrupt ({}); moved to {}; starting with factory defaults", file.string(),
                   failure->reason, aside.filename().string());
    }
    return std::nullopt;
  }
  auto& ok = std::get<ParsedFile>(parsed);
  spdlog::info("loaded {} stored objects from {}{}", ok.image.objects.size(), file.string(),
               ok.image.script.is_null() ? " (no script)" : " and the stored script");
  return std::move(ok);
}

void StateDir::warn_ignored(const std::vector<std::string>& keys) const {
  if (keys.empty()) return;
  std::string first;
  for (std::size_t i = 0; i < keys.size() && i < 3; ++i) {
    if (i > 0) first += ", ";
    first += keys[i];
  }
  spdlog::warn("state file {}: {} stored values ignored (unknown object or invalid value), first: {}",
               state_file().string(), keys.size(), first);
}

std::optional<std::int64_t> StateDir::load_plant(std::string_view model) const {
  std::string error;
  const auto text = read_file(plant_file(), error);
  if (!text) return std::nullopt;
  return parse_plant(*text, model);
}

}  // namespace mcemu::persistence
