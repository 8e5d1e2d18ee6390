// Where SAVE puts variables and LOAD finds them (faulhaber.md §9.8). The interpreter is pure: it
// calls this interface synchronously; the owner makes the values durable (the server: the state
// directory's `faulhaber/variables.json`, written crash-safe by the persistence worker).
//
// Contract: save() is one SAVE statement (its variables in the order written, duplicates kept) and
// must not fail from the program's point of view; load() answers what the last save of that
// variable stored, nullopt if it was never saved (LOAD then gives 0).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>

#include "scripting/basic/program.hpp"

namespace mcemu::basic {

struct SavedVariable {
  std::uint8_t var = 0;  // 0 = a … 25 = z
  std::int32_t value = 0;
  bool operator==(const SavedVariable&) const = default;
};

class VariableStorage {
 public:
  virtual ~VariableStorage() = default;
  virtual std::optional<std::int32_t> load(std::uint8_t var) const = 0;
  virtual void save(std::span<const SavedVariable> values) = 0;
};

// The values in memory: tests, and the owner's cache in front of the file (it restores the file's
// values with set() at start-up and writes the file from values() in on_saved).
class MemoryVariables final : public VariableStorage {
 public:
  using Values = std::array<std::optional<std::int32_t>, k_variable_count>;

  explicit MemoryVariables(std::function<void(const Values&)> on_saved = {}) : on_saved_(std::move(on_saved)) {}

  std::optional<std::int32_t> load(std::uint8_t var) const override {
    return var < values_.size() ? values_[var] : std::nullopt;
  }
  void save(std::span<const SavedVariable> values) override {
    for (const auto& v : values) {
      if (v.var < values_.size()) values_[v.var] = v.value;
    }
    ++saves_;
    if (on_saved_) on_saved_(values_);
  }

  void set(std::uint8_t var, std::optional<std::int32_t> value) {
    if (var < values_.size()) values_[var] = value;
  }
  const Values& values() const { return values_; }
  std::uint64_t saves() const { return saves_; }

 private:
  Values values_{};
  std::uint64_t saves_ = 0;
  std::function<void(const Values&)> on_saved_;
};

}  // namespace mcemu::basic
