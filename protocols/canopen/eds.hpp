// CiA 306 electronic data sheet (EDS) of a dictionary (slcan-canopen.md §12 EDS-01,
// object-dictionary.md §8.5: the same walk as --dump-od). Pure: the caller passes the date.
//
// Layout: [FileInfo], [DeviceInfo], [DummyUsage], [Comments], then [MandatoryObjects] (1000h,
// 1001h, 1018h), [OptionalObjects] (the other 1000h–1FFFh and 6000h–FFFFh) and
// [ManufacturerObjects] (2000h–5FFFh), each followed by its objects: one section per VAR
// (`[6041]`), one per ARRAY/RECORD with `SubNumber` (`[1018]`) and one per sub-index
// (`[1018sub1]`). Values are the dictionary's current values (the factory image when built for a
// dump), numbers in hexadecimal (`0x…`) except negative ones (decimal), COB-IDs absolute (for the
// node-id in use, factory 50). The PDO mapping is the fixed one of the XDDs: Granularity=0.
#pragma once

#include <string>

#include "drive/od/dictionary.hpp"

namespace mcemu::canopen {

struct EdsInfo {
  std::string file_name;    // e.g. "MC349.eds"
  std::string vendor_name;  // e.g. "Fullmo"
  std::string description;  // one line
  std::string date;         // mm-dd-yyyy (CiA 306)
  std::string time;         // hh:mm(AM|PM)
};

std::string make_eds(const od::ObjectDictionary& od, const EdsInfo& info);

}  // namespace mcemu::canopen
