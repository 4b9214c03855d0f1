#include "server/api/webhooks.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace corridor::server {
namespace {

TEST(WebhookUrlTest, TakesHttpAndHttpsUrlsApart) {
  HttpUrl u = ParseHttpUrl("http://127.0.0.1:9000/hooks/robot?x=1");
  EXPECT_FALSE(u.tls);
  EXPECT_EQ(u.host, "127.0.0.1");
  EXPECT_EQ(u.port, "9000");
  EXPECT_EQ(u.target, "/hooks/robot?x=1");
  u = ParseHttpUrl("https://lift.example.org");
  EXPECT_TRUE(u.tls);
  EXPECT_EQ(u.port, "443");
  EXPECT_EQ(u.target, "/");
  u = ParseHttpUrl("http://[::1]:8081?a=b");
  EXPECT_EQ(u.host, "::1");
  EXPECT_EQ(u.target, "/?a=b");
}

TEST(WebhookUrlTest, RefusesWhatIsNotAnHttpUrl) {
  for (const char* bad : {"", "ftp://host/x", "http://", "http://user:pw@host/", "http://host:99999/",
                          "http://host/a b", "http://host/#frag", "//host/x", "http://host:0/"}) {
    EXPECT_THROW(ParseHttpUrl(bad), std::invalid_argument) << bad;
  }
}

TEST(WebhookSignatureTest, IsHmacSha256InHex) {
  // RFC 4231, test case 2.
  EXPECT_EQ(WebhookSignature("Jefe", "what do ya want for nothing?"),
            "sha256=5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
}

}  // namespace
}  // namespace corridor::server
