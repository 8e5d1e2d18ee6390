// The object dictionary of a FAULHABER MotionController V3.0 preset (faulhaber.md §8): the CiA 301
// basics, the CiA 402 objects the drive core uses and the FAULHABER objects 2310h–2400h and 3005h.
// Hand-written (there is no FAULHABER device description in the repository; docs/decisions/0008);
// no MovingCap manufacturer object (3xxxh–5xxxh of the XDDs) is part of it.
#pragma once

#include <vector>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::od {

// Entries with type, access, class, factory value (identity from preset.identity, then
// preset.factory_values for entries that exist) and the write limits of faulhaber.md §6–§8.
std::vector<EntryInfo> build_faulhaber_entries(const model::ModelPreset& preset);

}  // namespace mcemu::od
