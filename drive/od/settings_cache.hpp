// A value derived from a dictionary's settings, recomputed only when a setting changed (issue 26):
// ObjectDictionary::settings_generation() counts every change of an entry a master can write
// (rw/wo) and every bulk load, so a value computed from such entries stays right while that count
// stands. The drive reads a few of them in every step (the enable masks of 3511h…351Ah, the owned
// outputs of 3611h…3614h); a fleet's drives would otherwise fetch them from memory each time.
//
// PURE. The derivation must read only rw/wo entries of the dictionary it is asked with.
#pragma once

#include <cstdint>

#include "drive/od/dictionary.hpp"

namespace mcemu::od {

template <class T>
class SettingsCache {
 public:
  // The cached value, or compute() (a T) once the settings have changed since it was taken.
  template <class Compute>
  const T& get(const ObjectDictionary& od, Compute&& compute) {
    const std::uint64_t generation = od.settings_generation();
    if (!valid_ || generation_ != generation) {
      value_ = compute();
      generation_ = generation;
      valid_ = true;
    }
    return value_;
  }

 private:
  T value_{};
  std::uint64_t generation_ = 0;
  bool valid_ = false;
};

}  // namespace mcemu::od
