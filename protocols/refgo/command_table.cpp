// The RefGo command table (refgo.md §6): one row per command word.
#include <array>
#include <cstdint>

#include "protocols/refgo/commands.hpp"

namespace mcemu::refgo {

namespace {

constexpr IntRange k_output{1, 4};
constexpr IntRange k_input{1, 10};

constexpr std::array k_table{
    CommandRow{"G", ArgShape::optional_int, k_i32, cmd::go_absolute},
    CommandRow{"GW", ArgShape::optional_int, k_i32, cmd::go_relative},
    CommandRow{"SM", ArgShape::none, k_any, cmd::stop_motion},
    CommandRow{"CM", ArgShape::none, k_any, cmd::continue_motion},
    CommandRow{"PWC", ArgShape::none, k_any, cmd::power_continue},
    CommandRow{"PQ", ArgShape::none, k_any, cmd::power_quit},
    CommandRow{"REF", ArgShape::optional_int, k_any, cmd::home},
    CommandRow{"JP", ArgShape::optional_int, k_u32, cmd::jog_positive},
    CommandRow{"JN", ArgShape::optional_int, k_u32, cmd::jog_negative},
    CommandRow{"RR", ArgShape::optional_int, k_i32, cmd::back_and_forth},
    CommandRow{"OR", ArgShape::objects, k_any, cmd::object_read},
    CommandRow{"OW", ArgShape::objects, k_any, cmd::object_write},
    CommandRow{"TP", ArgShape::none, k_any, cmd::tell_position},
    CommandRow{"TPSR", ArgShape::none, k_any, cmd::tell_tpsr},
    CommandRow{"TS", ArgShape::none, k_any, cmd::tell_status},
    CommandRow{"TI", ArgShape::optional_int, k_input, cmd::tell_input},
    CommandRow{"SP", ArgShape::required_int, k_u32, cmd::speed},
    CommandRow{"AC", ArgShape::required_int, k_u32, cmd::acceleration},
    CommandRow{"DE", ArgShape::required_int, k_u32, cmd::deceleration},
    CommandRow{"ACV", ArgShape::required_int, k_u32, cmd::jerk},
    CommandRow{"PO", ArgShape::required_int, k_i32, cmd::target},
    CommandRow{"WA", ArgShape::required_int, k_i32, cmd::target},
    CommandRow{"SO", ArgShape::required_int, k_output, cmd::set_output},
    CommandRow{"CO", ArgShape::required_int, k_output, cmd::clear_output},
    CommandRow{"RW", ArgShape::required_int, k_i32, cmd::repeat_way},
    CommandRow{"WT", ArgShape::required_int, k_u32, cmd::wait_time},
};

// Every command word has 1–4 letters, so a word packs into one integer (first letter in the top
// byte; a shorter word leaves low zero bytes) and the lookup compares integers, not strings: it runs
// for every line a client sends.
constexpr std::size_t k_max_word = 4;

constexpr std::uint32_t pack(std::string_view word) {
  std::uint32_t key = 0;
  for (std::size_t i = 0; i < k_max_word; ++i) {
    key = key << 8U | (i < word.size() ? static_cast<unsigned char>(word[i]) : 0U);
  }
  return key;
}

constexpr auto k_keys = [] {
  std::array<std::uint32_t, k_table.size()> keys{};
  for (std::size_t i = 0; i < k_table.size(); ++i) keys[i] = pack(k_table[i].word);
  return keys;
}();

constexpr bool words_fit() {
  for (const auto& row : k_table) {
    if (row.word.empty() || row.word.size() > k_max_word) return false;
  }
  return true;
}
static_assert(words_fit(), "find_command packs words of 1-4 letters");

}  // namespace

std::span<const CommandRow> command_table() { return k_table; }

const CommandRow* find_command(std::string_view word) {
  if (word.empty() || word.size() > k_max_word) return nullptr;
  const std::uint32_t key = pack(word);
  for (std::size_t i = 0; i < k_keys.size(); ++i) {
    if (k_keys[i] == key) return &k_table[i];
  }
  return nullptr;
}

}  // namespace mcemu::refgo
