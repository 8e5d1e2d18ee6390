// The cross-site check of web.md §1.3, one row per header combination.
#include "web/api/origin.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace mcemu::web::api {
namespace {

struct OriginCase {
  const char* name;
  std::vector<std::pair<std::string, std::string>> headers;
  bool cross_site;
};

class OriginCheck : public ::testing::TestWithParam<OriginCase> {};

TEST_P(OriginCheck, Decides) {
  Request r = make_request("GET", "/api/v1/ws");
  r.headers = GetParam().headers;
  EXPECT_EQ(is_cross_site(r), GetParam().cross_site) << GetParam().name;
}

INSTANTIATE_TEST_SUITE_P(
    Table, OriginCheck,
    ::testing::Values(
        OriginCase{"no headers (python-requests, curl)", {{"host", "127.0.0.1:8080"}}, false},
        OriginCase{"no headers at all", {}, false},
        OriginCase{"same origin with port", {{"host", "127.0.0.1:8080"}, {"origin", "http://127.0.0.1:8080"}}, false},
        OriginCase{"default port both ways", {{"host", "drive"}, {"origin", "http://drive"}}, false},
        OriginCase{"explicit :80 in origin", {{"host", "drive"}, {"origin", "http://drive:80"}}, false},
        OriginCase{"explicit :80 in host", {{"host", "drive:80"}, {"origin", "http://drive"}}, false},
        OriginCase{"host case-insensitive", {{"host", "Drive.Local:81"}, {"origin", "HTTP://drive.local:81"}}, false},
        OriginCase{"IPv6", {{"host", "[::1]:8080"}, {"origin", "http://[::1]:8080"}}, false},
        OriginCase{"trailing slash tolerated", {{"host", "a:1"}, {"origin", "http://a:1/"}}, false},
        OriginCase{"other port", {{"host", "127.0.0.1:8080"}, {"origin", "http://127.0.0.1:8081"}}, true},
        OriginCase{"other host", {{"host", "127.0.0.1:8080"}, {"origin", "http://evil.example:8080"}}, true},
        OriginCase{"https default 443 vs host 80", {{"host", "drive"}, {"origin", "https://drive"}}, true},
        OriginCase{"origin null", {{"host", "drive"}, {"origin", "null"}}, true},
        OriginCase{"origin without host header", {{"origin", "http://drive"}}, true},
        OriginCase{"origin with a path", {{"host", "a:1"}, {"origin", "http://a:1/x"}}, true},
        OriginCase{"origin with userinfo", {{"host", "a:1"}, {"origin", "http://u@a:1"}}, true},
        OriginCase{"unknown scheme without port", {{"host", "a"}, {"origin", "ftp://a"}}, true},
        OriginCase{"port 0", {{"host", "a:0"}, {"origin", "http://a:0"}}, true},
        OriginCase{"port too large", {{"host", "a:70000"}, {"origin", "http://a:70000"}}, true},
        OriginCase{"garbage port", {{"host", "a:8x"}, {"origin", "http://a:8x"}}, true},
        OriginCase{"empty origin", {{"host", "a"}, {"origin", ""}}, true},
        OriginCase{"fetch-site same-origin", {{"host", "a"}, {"sec-fetch-site", "same-origin"}}, false},
        OriginCase{"fetch-site none (typed URL)", {{"host", "a"}, {"sec-fetch-site", "none"}}, false},
        OriginCase{"fetch-site same-site", {{"host", "a"}, {"sec-fetch-site", "same-site"}}, true},
        OriginCase{"fetch-site cross-site", {{"host", "a"}, {"sec-fetch-site", "cross-site"}}, true},
        OriginCase{"fetch-site same-origin but foreign origin",
                   {{"host", "a:1"}, {"sec-fetch-site", "same-origin"}, {"origin", "http://b:1"}},
                   true},
        OriginCase{"fetch-site cross-site but matching origin",
                   {{"host", "a:1"}, {"sec-fetch-site", "cross-site"}, {"origin", "http://a:1"}},
                   true},
        OriginCase{"both same-origin",
                   {{"host", "a:1"}, {"sec-fetch-site", "same-origin"}, {"origin", "http://a:1"}},
                   false}));

TEST(OriginParse, Authorities) {
  EXPECT_EQ(parse_origin("http://Example.com:8080"), (Authority{"example.com", 8080}));
  EXPECT_EQ(parse_origin("wss://x"), (Authority{"x", 443}));
  EXPECT_EQ(parse_origin("ws://x"), (Authority{"x", 80}));
  EXPECT_EQ(parse_origin("x:80"), std::nullopt);
  EXPECT_EQ(parse_host("[::1]"), (Authority{"[::1]", 80}));
  EXPECT_EQ(parse_host("[::1"), std::nullopt);
  EXPECT_EQ(parse_host(":80"), std::nullopt);
  EXPECT_EQ(parse_host("a b"), std::nullopt);
}

TEST(OriginRefusal, Is403WithErrorBody) {
  const Response r = cross_site_refused();
  EXPECT_EQ(r.status, 403);
  EXPECT_EQ(r.content_type, "application/json");
  const auto j = nlohmann::json::parse(r.body);
  EXPECT_EQ(j["error"]["code"], "cross-site");
}

}  // namespace
}  // namespace mcemu::web::api
