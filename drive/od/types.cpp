#include "drive/od/types.hpp"

namespace mcemu::od {

std::string_view to_string(DataType t) {
  switch (t) {
    case DataType::boolean: return "BOOLEAN";
    case DataType::integer8: return "INTEGER8";
    case DataType::integer16: return "INTEGER16";
    case DataType::integer32: return "INTEGER32";
    case DataType::unsigned8: return "UNSIGNED8";
    case DataType::unsigned16: return "UNSIGNED16";
    case DataType::unsigned32: return "UNSIGNED32";
    case DataType::visible_string: return "VISIBLE_STRING";
  }
  return "?";
}

std::optional<DataType> data_type_from_string(std::string_view n) {
  for (auto t : {DataType::boolean, DataType::integer8, DataType::integer16, DataType::integer32, DataType::unsigned8,
                 DataType::unsigned16, DataType::unsigned32, DataType::visible_string}) {
    if (to_string(t) == n) return t;
  }
  return std::nullopt;
}

std::string_view to_string(Access a) {
  switch (a) {
    case Access::ro: return "ro";
    case Access::wo: return "wo";
    case Access::rw: return "rw";
    case Access::const_: return "const";
  }
  return "?";
}

std::string_view to_string(PdoFlag p) {
  switch (p) {
    case PdoFlag::no: return "no";
    case PdoFlag::rpdo: return "RPDO";
    case PdoFlag::tpdo: return "TPDO";
    case PdoFlag::optional: return "optional";
  }
  return "?";
}

std::string_view to_string(EntryClass c) {
  switch (c) {
    case EntryClass::const_: return "const";
    case EntryClass::live: return "live";
    case EntryClass::param: return "param";
    case EntryClass::comm: return "comm";
    case EntryClass::proc: return "proc";
    case EntryClass::cmd: return "cmd";
  }
  return "?";
}

std::string_view to_string(Origin o) {
  switch (o) {
    case Origin::sdo: return "sdo";
    case Origin::refgo: return "refgo";
    case Origin::script: return "script";
    case Origin::web: return "web";
    case Origin::internal: return "internal";
  }
  return "?";
}

}  // namespace mcemu::od
