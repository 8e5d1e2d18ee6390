// SDO abort codes: the one error vocabulary of the object dictionary (object-dictionary.md §4).
// Other layers (RefGo error replies, HTTP bodies, mcdrive return values) map from these.
#pragma once

#include <cstdint>
#include <string_view>
#include <system_error>
#include <variant>

namespace mcemu::od {

enum class AbortCode : std::uint32_t {
  none = 0,
  pending = 1,  // internal only: Store/Restore completes later (object-dictionary.md §3.3)
  toggle_bit = 0x05030000,
  sdo_timeout = 0x05040000,
  unknown_command = 0x05040001,
  invalid_block_size = 0x05040002,
  invalid_sequence = 0x05040003,
  crc_error = 0x05040004,
  out_of_memory = 0x05040005,
  unsupported_access = 0x06010000,
  write_only = 0x06010001,
  read_only = 0x06010002,
  no_object = 0x06020000,
  not_mappable = 0x06040041,
  pdo_length = 0x06040042,
  incompatible = 0x06040043,
  internal_incompatibility = 0x06040047,
  hardware_error = 0x06060000,
  type_mismatch = 0x06070010,
  length_too_high = 0x06070012,
  length_too_low = 0x06070013,
  no_sub = 0x06090011,
  invalid_value = 0x06090030,
  value_too_high = 0x06090031,
  value_too_low = 0x06090032,
  max_below_min = 0x06090036,
  resource_unavailable = 0x060A0023,
  general = 0x08000000,
  cannot_store = 0x08000020,
  local_control = 0x08000021,
  device_state = 0x08000022,
  no_dictionary = 0x08000023,
  no_data = 0x08000024,
};

constexpr std::uint32_t to_u32(AbortCode c) { return static_cast<std::uint32_t>(c); }

// CiA 301 text of a code ("Object does not exist in the object dictionary"); generic text for
// codes not in the table.
std::string_view description(AbortCode c);

const std::error_category& abort_category();
inline std::error_code make_error_code(AbortCode c) { return {static_cast<int>(c), abort_category()}; }

// A T or the abort code that prevented it (std::expected is C++23).
template <typename T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(AbortCode code) : v_(code) {}       // NOLINT(google-explicit-constructor)
  [[nodiscard]] bool ok() const { return std::holds_alternative<T>(v_); }
  explicit operator bool() const { return ok(); }
  const T& value() const { return std::get<T>(v_); }
  T& value() { return std::get<T>(v_); }
  const T& operator*() const { return value(); }
  T& operator*() { return value(); }
  const T* operator->() const { return &value(); }
  [[nodiscard]] AbortCode error() const { return ok() ? AbortCode::none : std::get<AbortCode>(v_); }

 private:
  std::variant<T, AbortCode> v_;
};

}  // namespace mcemu::od

template <>
struct std::is_error_code_enum<mcemu::od::AbortCode> : std::true_type {};
