// The pure HTTP router: info, objects, store (web.md §1.3, §7, §8.1, §8.3).
#include "web/api/router.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "drive/model/model_preset.hpp"

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

struct Fixture {
  Fixture()
      : od(*model::find_preset("MC349")),
        router(od,
               [] {
                 Info i;
                 i.model = "MC349";
                 return i;
               },
               {}) {}
  Response call(std::string method, std::string target, std::string body = "", std::string type = "") {
    Response out;
    int calls = 0;
    router.handle(Request{std::move(method), std::move(target), std::move(type), std::move(body)}, [&](Response r) {
      out = std::move(r);
      ++calls;
    });
    EXPECT_EQ(calls, 1);
    return out;
  }
  od::ObjectDictionary od;
  Router router;
};

TEST(Router, Info) {
  Fixture f;
  auto r = f.call("GET", "/api/v1/info");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(json::parse(r.body)["model"], "MC349");
  EXPECT_EQ(json::parse(r.body)["emulator"], "mcemu");
  EXPECT_EQ(f.call("DELETE", "/api/v1/info").status, 405);
}

TEST(Router, ObjectsReadAndWrite) {
  Fixture f;
  auto r = f.call("GET", "/api/v1/objects/0x6083/0");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(json::parse(r.body)["value"], 1000);
  EXPECT_EQ(json::parse(r.body)["index"], "6083h");
  r = f.call("PUT", "/api/v1/objects/6083h/00h", R"({"value": 1500})");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(json::parse(r.body)["value"], 1500);
  EXPECT_EQ(*f.od.read_number(0x6083, 0), 1500);
  r = f.call("PUT", "/api/v1/objects/6041/0", R"({"value": 1})");
  EXPECT_EQ(r.status, 409);
  EXPECT_EQ(json::parse(r.body)["error"]["abortCode"], "06010002h");
  EXPECT_EQ(f.call("GET", "/api/v1/objects/7000/0").status, 404);
  EXPECT_EQ(f.call("GET", "/api/v1/objects/6041/1").status, 404);
  EXPECT_EQ(f.call("GET", "/api/v1/objects/60zz/0").status, 400);
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/6083/0", "{").status, 400);
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/6083/0", R"({"value": 0})").status, 409);
  r = f.call("POST", "/api/v1/objects/read", R"({"objects": [["6083", 0], ["7000", 0]]})", "application/json");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(json::parse(r.body)["values"][0], 1500);
  EXPECT_EQ(json::parse(r.body)["values"][1]["abortCode"], "06020000h");
  EXPECT_EQ(json::parse(f.call("GET", "/api/v1/objects").body).size(), f.od.size());
}

TEST(Router, PostNeedsJsonContentType) {
  Fixture f;
  EXPECT_EQ(f.call("POST", "/api/v1/objects/read", R"({"objects": []})", "text/plain").status, 415);
  EXPECT_EQ(f.call("POST", "/api/v1/store", "", "application/x-www-form-urlencoded").status, 415);
}

TEST(Router, StoreCompletesWhenTheHookCompletes) {
  Fixture f;
  od::Done parked;
  f.od.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    parked = std::move(*r.done);
    return od::AbortCode::pending;
  });
  std::optional<Response> out;
  f.router.handle(Request{"POST", "/api/v1/store", "application/json", "{}"}, [&](Response r) { out = r; });
  EXPECT_FALSE(out) << "no answer before the store completes";
  parked(od::AbortCode::hardware_error);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->status, 409);
  EXPECT_EQ(json::parse(out->body)["error"]["abortCode"], "06060000h");
}

// Bad input never crashes and never corrupts (README ground rule): malformed targets and bodies of
// the object API get a 4xx with a JSON error, and the entry keeps its value.
struct BadCall {
  const char* method;
  const char* target;
  const char* body;
  int status;
};

class RouterBadInput : public ::testing::TestWithParam<BadCall> {};

TEST_P(RouterBadInput, Is4xxJsonAndChangesNothing) {
  Fixture f;
  const auto& c = GetParam();
  const std::int64_t mode = *f.od.read_number(0x6060, 0);
  const auto r = f.call(c.method, c.target, c.body, "application/json");
  EXPECT_EQ(r.status, c.status) << r.body;
  const auto body = json::parse(r.body, nullptr, false);
  ASSERT_FALSE(body.is_discarded()) << r.body;
  EXPECT_TRUE(body.contains("error")) << r.body;
  EXPECT_EQ(*f.od.read_number(0x6083, 0), 1000);
  EXPECT_EQ(*f.od.read_number(0x6060, 0), mode);
}

INSTANTIATE_TEST_SUITE_P(
    Table, RouterBadInput,
    ::testing::Values(BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": "abc"})", 409},  // 06070010h
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 1.5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": null})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": [1]})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": {"a": 1}})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"val": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"([1500])", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"(1500)", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", "", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", "\xFF\xFE{", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 18446744073709551616})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 1e300})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": -2147483649})", 409},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 4294967296})", 409},
                      BadCall{"PUT", "/api/v1/objects/6060/0", R"({"value": 99})", 409},
                      BadCall{"PUT", "/api/v1/objects/6083/256", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/10000/0", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects//0", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/-6083/0", R"({"value": 5})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": "6083"})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [[1]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [["6083"]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [["6083", "zz"]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [[null, 0]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({})", 400},
                      BadCall{"POST", "/api/v1/objects/read", "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]", 400}));

TEST(Router, UnknownPathIs404Html) {
  Fixture f;
  auto r = f.call("GET", "/nothing");
  EXPECT_EQ(r.status, 404);
  EXPECT_NE(r.body.find("/index.html"), std::string::npos);
}

TEST(HexToken, Forms) {
  EXPECT_EQ(parse_hex_token("6041", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("6041h", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("0x6041", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("01h", 0xFF), 1u);
  EXPECT_FALSE(parse_hex_token("100", 0xFF));
  EXPECT_FALSE(parse_hex_token("", 0xFF));
  EXPECT_FALSE(parse_hex_token("h", 0xFF));
}

}  // namespace
}  // namespace mcemu::web::api
