// Value-set validators of the dictionary builders (object-dictionary.md §5 ".30"): the allowed values
// are template arguments, so a validator is a captureless function that std::function keeps
// without allocating (a drive's dictionary is built in ≤ 50 us, issue 26). Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "drive/od/dictionary.hpp"

namespace mcemu::od {

// Only the listed values.
template <std::int64_t... Allowed>
Validator one_of() {
  return [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
    return ((v == Allowed) || ...) ? AbortCode::none : AbortCode::invalid_value;
  };
}

// lo … hi and the listed values.
template <std::int64_t Lo, std::int64_t Hi, std::int64_t... More>
Validator range_set() {
  return [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
    return (v >= Lo && v <= Hi) || ((v == More) || ...) ? AbortCode::none : AbortCode::invalid_value;
  };
}

}  // namespace mcemu::od
