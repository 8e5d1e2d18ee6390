// The "faulhaber" config section: defaults, every key, and one error line naming the key.
#include "protocols/faulhaber/config.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace mcemu::faulhaber {
namespace {

using nlohmann::json;

TEST(FaulhaberConfig, Defaults) {
  const auto c = faulhaber_config_from_json(json::object());
  EXPECT_EQ(c.node_id, 1);
  EXPECT_TRUE(c.crc_check);
  EXPECT_EQ(c.port.response_delay, Millis(0));
  EXPECT_EQ(c.port.queue_limit_bytes, 65536u);
  EXPECT_EQ(c.port.inter_byte_timeout, Millis(50));
  EXPECT_EQ(factory_settings(c), 0x00030000u);
}

TEST(FaulhaberConfig, Keys) {
  const auto c = faulhaber_config_from_json(json::parse(
      R"({"node_id": 5, "crc_check": false, "response_delay_ms": 3, "queue_limit_bytes": 4096,
          "device_name": "MC 5010", "serial": 7, "autostart": 1, "basic_statements_per_ms": 20})"));
  EXPECT_EQ(c.node_id, 5);
  EXPECT_FALSE(c.crc_check);
  EXPECT_EQ(factory_settings(c), 0x00830000u);
  EXPECT_EQ(c.port.response_delay, Millis(3));
  EXPECT_EQ(c.port.queue_limit_bytes, 4096u);
}

TEST(FaulhaberConfig, BadValuesNameTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"node_id": 0})", "faulhaber.node_id: must be 1 … 255"},
      {R"({"node_id": 256})", "faulhaber.node_id: must be 1 … 255"},
      {R"({"node_id": "1"})", "faulhaber.node_id: must be an integer"},
      {R"({"crc_check": 1})", "faulhaber.crc_check: must be true or false"},
      {R"({"response_delay_ms": -1})", "faulhaber.response_delay_ms: must be 0 … 10000"},
      {R"({"response_delay_ms": 1.5})", "faulhaber.response_delay_ms: must be an integer"},
      {R"({"queue_limit_bytes": 10})", "faulhaber.queue_limit_bytes: must be 1024 … 16777216"},
      {R"({"nodeid": 1})", "faulhaber.nodeid: unknown key"},
  };
  for (const auto& [text, message] : cases) {
    try {
      (void)faulhaber_config_from_json(json::parse(text));
      ADD_FAILURE() << text << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), message) << text;
    }
  }
  EXPECT_THROW(faulhaber_config_from_json(json::array()), std::invalid_argument);
}

// The keys other parts read and check themselves (the bundle, the server's connection limit) pass.
TEST(FaulhaberConfig, KeysOfOtherPartsPass) {
  for (const char* text : {R"({"device_name": "X"})", R"({"serial": 7})", R"({"autostart": true})",
                           R"({"basic_statements_per_ms": 50})", R"({"max_clients": 2})"}) {
    EXPECT_NO_THROW((void)faulhaber_config_from_json(json::parse(text))) << text;
  }
}

}  // namespace
}  // namespace mcemu::faulhaber
