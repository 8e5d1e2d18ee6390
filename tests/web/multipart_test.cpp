// multipart/form-data (RFC 7578) for the script upload of web.md §6.1: the boundary parameter and
// the parts, with the bodies browsers and python-requests send.
#include "web/api/multipart.hpp"

#include <gtest/gtest.h>

namespace mcemu::web::api {
namespace {

TEST(Multipart, Boundary) {
  EXPECT_EQ(multipart_boundary("multipart/form-data; boundary=abc123"), "abc123");
  EXPECT_EQ(multipart_boundary("Multipart/Form-Data;BOUNDARY=\"a b:c\""), "a b:c") << "case and quotes";
  EXPECT_EQ(multipart_boundary("multipart/form-data; charset=utf-8; boundary=----WebKitFormBoundaryx7"),
            "----WebKitFormBoundaryx7");
  for (const char* bad : {"text/plain; boundary=x", "multipart/form-data",
                          "multipart/form-data; boundary=", "multipart/form-data; boundary=\"open",
                          "multipart/mixed; boundary=x", "", "multipart/form-data; boundary"}) {
    EXPECT_FALSE(multipart_boundary(bad)) << bad;
  }
  EXPECT_FALSE(multipart_boundary("multipart/form-data; boundary=" + std::string(71, 'x'))) << "RFC 2046: ≤ 70";
  EXPECT_TRUE(multipart_boundary("multipart/form-data; boundary=" + std::string(70, 'x')));
}

TEST(Multipart, PartsOfARequestsBody) {
  // python-requests 2.28 (urllib3 encode_multipart_formdata), as Fullmo's uploader sends it
  const std::string body =
      "--b0\r\nContent-Disposition: form-data; name=\"Python script file for MovingCap CODE\"; "
      "filename=\"x.py\"\r\nContent-Type: text/x-python\r\n\r\nprint(1)\r\n\r\n--b0--\r\n";
  const auto parts = parse_multipart(body, "b0");
  ASSERT_TRUE(parts);
  ASSERT_EQ(parts->size(), 1u);
  EXPECT_EQ((*parts)[0].name, "Python script file for MovingCap CODE");
  EXPECT_EQ((*parts)[0].filename, "x.py");
  EXPECT_EQ((*parts)[0].content_type, "text/x-python");
  EXPECT_EQ((*parts)[0].content, "print(1)\r\n") << "only the CRLF before the delimiter belongs to it";
}

TEST(Multipart, BrowserBodyWithSeveralPartsPreambleAndEpilogue) {
  const std::string body =
      "preamble\r\n--XyZ\r\ncontent-disposition: form-data; name=\"a\"\r\n\r\n1\r\n"
      "--XyZ  \r\nCONTENT-DISPOSITION: form-data; name=\"f\"; filename=\"q\\\"uote.py\"\r\n\r\n"
      "x --XyZ is not a delimiter here\r\n-- neither\r\n--XyZ--\r\nepilogue";
  const auto parts = parse_multipart(body, "XyZ");
  ASSERT_TRUE(parts);
  ASSERT_EQ(parts->size(), 2u);
  EXPECT_EQ((*parts)[0].name, "a");
  EXPECT_EQ((*parts)[0].content, "1");
  EXPECT_FALSE((*parts)[0].filename);
  EXPECT_EQ((*parts)[1].name, "f");
  EXPECT_EQ((*parts)[1].filename, "q\"uote.py");
  EXPECT_EQ((*parts)[1].content, "x --XyZ is not a delimiter here\r\n-- neither");
}

TEST(Multipart, BinaryAndEmptyContent) {
  const std::string bytes("\0\xff\r\n\r\n\x80", 7);
  const std::string body = "--b\r\nContent-Disposition: form-data; name=\"f\"\r\n\r\n" + bytes +
                           "\r\n--b\r\nContent-Disposition: form-data; name=\"e\"\r\n\r\n\r\n--b--";
  const auto parts = parse_multipart(body, "b");
  ASSERT_TRUE(parts);
  ASSERT_EQ(parts->size(), 2u);
  EXPECT_EQ((*parts)[0].content, bytes);
  EXPECT_EQ((*parts)[1].content, "");
}

TEST(Multipart, MalformedBodies) {
  const std::string head = "--b\r\nContent-Disposition: form-data; name=\"f\"\r\n\r\n";
  for (const std::string& bad :
       {std::string("no delimiter at all"), head + "x",  // not closed
        std::string("--b\r\nContent-Disposition: form-data; name=\"f\"\r\nx\r\n--b--"),
        std::string("--b\r\nContent-Type: text/plain\r\n\r\nx\r\n--b--"),  // no name
        std::string("--b\r\nContent-Disposition: attachment; name=\"f\"\r\n\r\nx\r\n--b--"),
        std::string("--b\r\nContent-Disposition: form-data; filename=\"f\"\r\n\r\nx\r\n--b--"),
        std::string("--b\r\nContent-Disposition: form-data; name=\"f\r\n\r\nx\r\n--b--"),
        std::string("--bx\r\n") + "Content-Disposition: form-data; name=\"f\"\r\n\r\nx\r\n--b--",
        std::string("--b\r\nno colon\r\n\r\nx\r\n--b--")}) {
    EXPECT_FALSE(parse_multipart(bad, "b")) << bad;
  }
  EXPECT_EQ(parse_multipart("--b--", "b")->size(), 0u) << "no parts at all";
}

}  // namespace
}  // namespace mcemu::web::api
