#include "drive/od/abort_code.hpp"

#include <string>

namespace mcemu::od {

std::string_view description(AbortCode c) {
  switch (c) {
    case AbortCode::none: return "No error";
    case AbortCode::pending: return "Operation pending";
    case AbortCode::toggle_bit: return "Toggle bit not alternated";
    case AbortCode::sdo_timeout: return "SDO protocol timed out";
    case AbortCode::unknown_command: return "Client/server command specifier not valid or unknown";
    case AbortCode::invalid_block_size: return "Invalid block size";
    case AbortCode::invalid_sequence: return "Invalid sequence number";
    case AbortCode::crc_error: return "CRC error";
    case AbortCode::out_of_memory: return "Out of memory";
    case AbortCode::unsupported_access: return "Unsupported access to an object";
    case AbortCode::write_only: return "Attempt to read a write only object";
    case AbortCode::read_only: return "Attempt to write a read only object";
    case AbortCode::no_object: return "Object does not exist in the object dictionary";
    case AbortCode::not_mappable: return "Object cannot be mapped to the PDO";
    case AbortCode::pdo_length: return "The number and length of the objects to be mapped would exceed PDO length";
    case AbortCode::incompatible: return "General parameter incompatibility reason";
    case AbortCode::internal_incompatibility: return "General internal incompatibility in the device";
    case AbortCode::hardware_error: return "Access failed due to a hardware error";
    case AbortCode::type_mismatch: return "Data type does not match, length of service parameter does not match";
    case AbortCode::length_too_high: return "Data type does not match, length of service parameter too high";
    case AbortCode::length_too_low: return "Data type does not match, length of service parameter too low";
    case AbortCode::no_sub: return "Sub-index does not exist";
    case AbortCode::invalid_value: return "Invalid value for parameter";
    case AbortCode::value_too_high: return "Value of parameter written too high";
    case AbortCode::value_too_low: return "Value of parameter written too low";
    case AbortCode::max_below_min: return "Maximum value is less than minimum value";
    case AbortCode::resource_unavailable: return "Resource not available";
    case AbortCode::general: return "General error";
    case AbortCode::cannot_store: return "Data cannot be transferred or stored to the application";
    case AbortCode::local_control:
      return "Data cannot be transferred or stored to the application because of local control";
    case AbortCode::device_state:
      return "Data cannot be transferred or stored to the application because of the present device state";
    case AbortCode::no_dictionary:
      return "Object dictionary dynamic generation fails or no object dictionary is present";
    case AbortCode::no_data: return "No data available";
  }
  return "Unknown abort code";
}

namespace {
class AbortCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "sdo-abort"; }
  std::string message(int code) const override {
    return std::string(description(static_cast<AbortCode>(static_cast<std::uint32_t>(code))));
  }
};
}  // namespace

const std::error_category& abort_category() {
  static const AbortCategory category;
  return category;
}

}  // namespace mcemu::od
