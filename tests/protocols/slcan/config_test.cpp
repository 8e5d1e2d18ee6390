#include "protocols/slcan/config.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace mcemu::slcan {
namespace {

TEST(SlcanConfig, DefaultsAndValues) {
  const auto d = slcan_config_from_json(nlohmann::json::object());
  EXPECT_EQ(d.frame_ack, FrameAck::z);
  EXPECT_EQ(d.version, "1010");
  EXPECT_EQ(d.serial_digits, 4);
  EXPECT_FALSE(d.max_clients);
  EXPECT_EQ(d.queue_limit_bytes, 262144u);
  const auto c = slcan_config_from_json(nlohmann::json::parse(
      R"({"frame_ack":"none","version":"0102","serial_digits":8,"max_clients":2,"queue_limit_bytes":4096})"));
  EXPECT_EQ(c.frame_ack, FrameAck::none);
  EXPECT_EQ(c.version, "0102");
  EXPECT_EQ(c.serial_digits, 8);
  EXPECT_EQ(c.max_clients, 2);
  EXPECT_EQ(c.queue_limit_bytes, 4096u);
  EXPECT_EQ(slcan_config_from_json(nlohmann::json::parse(R"({"frame_ack":"cr"})")).frame_ack, FrameAck::cr);
}

TEST(SlcanConfig, BadValuesNameTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"frame_ack":"Z"})", "slcan.frame_ack"},
      {R"({"frame_ack":1})", "slcan.frame_ack"},
      {R"({"version":"101"})", "slcan.version"},
      {R"({"version":"10a0"})", "slcan.version"},
      {R"({"version":1010})", "slcan.version"},
      {R"({"serial_digits":6})", "slcan.serial_digits"},
      {R"({"max_clients":0})", "slcan.max_clients"},
      {R"({"queue_limit_bytes":"x"})", "slcan.queue_limit_bytes"},
      {R"({"queue_limit_bytes":10})", "slcan.queue_limit_bytes"},
      {R"({"bogus":1})", "slcan.bogus"},
  };
  for (const auto& [text, key] : cases) {
    try {
      (void)slcan_config_from_json(nlohmann::json::parse(text));
      ADD_FAILURE() << text << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(key + ":", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW((void)slcan_config_from_json(nlohmann::json::array()), std::invalid_argument);
}

}  // namespace
}  // namespace mcemu::slcan
