// What the fuzz targets share: fail() (a finding), check_dictionary() (the invariant that no input
// corrupts the dictionary) and Records (input-driven records). The real drive behind the session
// fuzzers is the one test fixture, tests/support/device_fixture.hpp, built fresh for every input so
// that a crash reproduces from its input alone.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "drive/od/dictionary.hpp"

namespace mcemu::fuzz {

// A finding: print it and abort, so that libFuzzer (and the replay runner) report the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

// Every stored value has the kind and range of its entry's data type (the checks every write path
// makes), so no input can leave the dictionary in a state a write could not have produced.
inline void check_dictionary(const od::ObjectDictionary& od) {
  od.for_each([](const od::EntryInfo& info, const od::Value& v) {
    const auto converted = od::convert_for_write(info, v);
    if (!converted) {
      fail("entry " + std::to_string(info.index) + "." + std::to_string(info.sub) + " (" + std::string(info.name) +
           ") holds a value its type refuses");
    }
  });
}

// Reads little input-driven records: [op][len][payload…], each field clamped to what is left.
class Records {
 public:
  Records(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  bool empty() const { return p_ >= end_; }
  std::uint8_t byte() { return p_ < end_ ? *p_++ : 0; }
  std::uint16_t u16() {
    const std::uint16_t lo = byte();
    return static_cast<std::uint16_t>(lo | (byte() << 8));
  }
  // A length-prefixed byte string (length byte, then up to that many bytes).
  std::string_view bytes() {
    const std::size_t want = byte();
    const std::size_t n = std::min<std::size_t>(want, static_cast<std::size_t>(end_ - p_));
    std::string_view s(reinterpret_cast<const char*>(p_), n);
    p_ += n;
    return s;
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

}  // namespace mcemu::fuzz
