// The embedded UI files (web.md §1.4, §1.5): lookup, caching headers, 304, the size budget and
// the offline rule.
#include "web/api/static_files.hpp"

#include <gtest/gtest.h>

#include <regex>

#include "web/assets/assets.hpp"

namespace mcemu::web::api {
namespace {

std::optional<std::string> header(const Response& r, std::string_view name) {
  for (const auto& [k, v] : r.headers) {
    if (k == name) return v;
  }
  return std::nullopt;
}

Request get(std::string target, std::vector<std::pair<std::string, std::string>> headers = {},
            std::string method = "GET") {
  Request r = make_request(std::move(method), std::move(target));
  r.headers = std::move(headers);
  return r;
}

TEST(Assets, TableIsSortedAndFindable) {
  const auto all = assets::all();
  ASSERT_FALSE(all.empty());
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_LT(all[i - 1].path, all[i].path);
  for (const auto& a : all) {
    EXPECT_EQ(assets::find(a.path), &a);
    EXPECT_EQ(a.path.front(), '/');
    EXPECT_FALSE(a.mime.empty());
    EXPECT_TRUE(std::regex_match(std::string(a.etag), std::regex("\"[0-9a-f]{20}\""))) << a.etag;
  }
  EXPECT_EQ(assets::find("/nope.html"), nullptr);
  EXPECT_EQ(assets::find(""), nullptr);
  EXPECT_EQ(assets::find("index.html"), nullptr);
}

TEST(Assets, StartPageAndStyleSheetAreEmbedded) {
  const auto* index = assets::find("/index.html");
  ASSERT_NE(index, nullptr);
  EXPECT_EQ(index->mime, "text/html; charset=utf-8");
  EXPECT_NE(index->bytes.find("<title>Info"), std::string_view::npos);
  EXPECT_NE(index->bytes.find("{{> header}}"), std::string_view::npos) << "a page template (pages.hpp)";
  EXPECT_NE(index->bytes.find("/static/mcemu.css"), std::string_view::npos);
  const auto* css = assets::find("/static/mcemu.css");
  ASSERT_NE(css, nullptr);
  EXPECT_EQ(css->mime, "text/css; charset=utf-8");
}

TEST(Assets, TotalSizeWithinOneMiB) {
  std::size_t total = 0;
  for (const auto& a : assets::all()) total += a.bytes.size();
  EXPECT_LE(total, 1024U * 1024U);
}

TEST(Assets, NothingLoadedFromOtherHosts) {
  // web.md §1.5 / §11.11: no http(s) reference except XML namespace names of the W3C.
  const std::regex url(R"(https?://[^\s"'<>)]*)", std::regex::icase);
  for (const auto& a : assets::all()) {
    const std::string text(a.bytes);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), url); it != std::sregex_iterator(); ++it) {
      EXPECT_EQ(it->str().rfind("http://www.w3.org/", 0), 0U) << a.path << ": " << it->str();
    }
  }
}

TEST(Assets, RootServesIndex) {
  const auto r = serve_asset(get("/"));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->body, assets::find("/index.html")->bytes);
}

TEST(StaticFiles, PagesAreNoStoreWithoutEtag) {
  const auto r = serve_asset(get("/index.html?x=1"));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->content_type, "text/html; charset=utf-8");
  EXPECT_EQ(header(*r, "Cache-Control"), "no-store");
  EXPECT_EQ(header(*r, "ETag"), std::nullopt);
  // a page is never answered 304: it is not cached, so a stale validator must not suppress it
  const auto again = serve_asset(get("/index.html", {{"if-none-match", "*"}}));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
}

TEST(StaticFiles, AssetsHaveEtagAndMaxAge) {
  const auto* css = assets::find("/static/mcemu.css");
  const auto r = serve_asset(get("/static/mcemu.css"));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->content_type, css->mime);
  EXPECT_EQ(r->body, css->bytes);
  EXPECT_EQ(header(*r, "ETag"), std::string(css->etag));
  EXPECT_EQ(header(*r, "Cache-Control"), "max-age=3600");
}

TEST(StaticFiles, HeadIsAnsweredLikeGet) {
  const auto g = serve_asset(get("/static/mcemu.css"));
  const auto h = serve_asset(get("/static/mcemu.css", {}, "HEAD"));
  ASSERT_TRUE(g && h);
  EXPECT_EQ(h->status, g->status);
  EXPECT_EQ(h->headers, g->headers);
  EXPECT_EQ(h->body, g->body);
}

struct InmCase {
  std::string header;
  int status;
};

class StaticFilesIfNoneMatch : public ::testing::TestWithParam<InmCase> {};

TEST_P(StaticFilesIfNoneMatch, Answers) {
  const std::string etag(assets::find("/static/mcemu.css")->etag);
  std::string h = GetParam().header;
  for (auto pos = h.find("ETAG"); pos != std::string::npos; pos = h.find("ETAG")) h.replace(pos, 4, etag);
  const auto r = serve_asset(get("/static/mcemu.css", {{"if-none-match", h}}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, GetParam().status) << h;
  if (r->status == 304) {
    EXPECT_TRUE(r->body.empty());
    EXPECT_EQ(header(*r, "ETag"), etag);
    EXPECT_EQ(header(*r, "Cache-Control"), "max-age=3600");
  }
}

INSTANTIATE_TEST_SUITE_P(Table, StaticFilesIfNoneMatch,
                         ::testing::Values(InmCase{"ETAG", 304}, InmCase{"*", 304}, InmCase{" * ", 304},
                                           InmCase{"\"x\", ETAG", 304}, InmCase{"ETAG,\"x\"", 304},
                                           InmCase{"W/ETAG", 304}, InmCase{"\"0000\"", 200}, InmCase{"", 200},
                                           InmCase{",,", 200}, InmCase{"\"x\" , \"y\"", 200}));

TEST(StaticFiles, EtagMatching) {
  EXPECT_TRUE(etag_matches("\"a\"", "\"a\""));
  EXPECT_FALSE(etag_matches("a", "\"a\""));
  EXPECT_FALSE(etag_matches("\"a", "\"a\""));
  EXPECT_TRUE(etag_matches("\"b\",\t\"a\"", "\"a\""));
}

TEST(StaticFiles, NotAnAssetOrNotGet) {
  EXPECT_FALSE(serve_asset(get("/nope.html")));
  EXPECT_FALSE(serve_asset(get("/static/")));
  EXPECT_FALSE(serve_asset(get("/api/v1/info")));
  EXPECT_FALSE(serve_asset(get("/index.html", {}, "POST")));
  EXPECT_FALSE(serve_asset(get("/static/mcemu.css", {}, "PUT")));
  EXPECT_FALSE(serve_asset(get("/static/../index.html")));
}

}  // namespace
}  // namespace mcemu::web::api
