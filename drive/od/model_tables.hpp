// The per-preset entry tables (object-dictionary.md §7–§10); used by ObjectDictionary's preset
// constructor and by tests that inspect the factory image.
#pragma once

#include <span>
#include <vector>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/tables/xdd_tables.hpp"

namespace mcemu::od {

std::span<const tables::XddEntry> xdd_table(model::Base base);
std::vector<EntryInfo> build_entries(const model::ModelPreset& preset);

}  // namespace mcemu::od
