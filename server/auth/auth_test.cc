#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "server/auth/accounts.h"
#include "server/auth/gate.h"
#include "server/auth/secrets.h"

namespace corridor::server::auth {
namespace {

namespace fs = std::filesystem;

class AccountsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor-accounts-" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST(SecretsTest, PasswordsAreArgon2idWithOwaspParametersAndVerifyOnlyThemselves) {
  const std::string hash = HashPassword("correct horse");
  EXPECT_EQ(hash.rfind("$argon2id$v=19$m=19456,t=2,p=1$", 0), 0u) << hash;
  EXPECT_TRUE(VerifyPassword(hash, "correct horse"));
  EXPECT_FALSE(VerifyPassword(hash, "correct horse "));
  EXPECT_FALSE(VerifyPassword("not a hash", "correct horse"));
  EXPECT_NE(HashPassword("correct horse"), hash) << "salted";
}

TEST(SecretsTest, RandomSecretsAndCodesUseTheirAlphabets) {
  EXPECT_EQ(RandomSecret(32).size(), 43u);
  EXPECT_NE(RandomSecret(32), RandomSecret(32));
  const std::string code = RandomCode(8);
  EXPECT_EQ(code.find_first_not_of("23456789ABCDEFGHJKMNPQRSTUVWXYZ"), std::string::npos) << code;
  EXPECT_EQ(SecretDigest("a").size(), 64u);
  EXPECT_TRUE(SameSecret("abc", "abc"));
  EXPECT_FALSE(SameSecret("abc", "abd"));
  EXPECT_FALSE(SameSecret("abc", "abcd"));
}

TEST(GateTest, WhoMayDoWhat) {
  const AuthOptions closed;
  AuthOptions open;
  open.anonymous_viewer = true;
  const Principal viewer{"v", Role::kViewer, "user", ""};
  const Principal op{"o", Role::kOperator, "token", "t"};
  EXPECT_FALSE(Allows(std::nullopt, Access::kViewer, false, closed));
  EXPECT_TRUE(Allows(std::nullopt, Access::kViewer, false, open));
  EXPECT_FALSE(Allows(std::nullopt, Access::kOperator, false, open));
  EXPECT_TRUE(Allows(std::nullopt, Access::kFace, true, closed)) << "the robot's own screen";
  EXPECT_FALSE(Allows(std::nullopt, Access::kFace, false, closed));
  EXPECT_TRUE(Allows(viewer, Access::kFace, false, closed));
  EXPECT_FALSE(Allows(viewer, Access::kOperator, false, closed));
  EXPECT_TRUE(Allows(op, Access::kOperator, false, closed));
  EXPECT_FALSE(Allows(op, Access::kAdmin, false, closed));
}

TEST(GateTest, HeadersAreParsedStrictly) {
  EXPECT_EQ(SessionFromCookies("a=1; corridor_session=abc; b=2"), "abc");
  EXPECT_EQ(SessionFromCookies("corridor_sessionx=abc"), "");
  EXPECT_EQ(SessionFromCookies(""), "");
  EXPECT_EQ(BearerToken("Bearer cor_x"), "cor_x");
  EXPECT_EQ(BearerToken("bearer  cor_x "), "cor_x");
  EXPECT_EQ(BearerToken("Basic dXNlcg=="), "");
  EXPECT_EQ(BearerToken("Bearer "), "");
  EXPECT_TRUE(SameOrigin("https://robot.local:8443", "robot.local:8443"));
  EXPECT_FALSE(SameOrigin("https://robot.local:8443", "robot.local:8080"));
  EXPECT_FALSE(SameOrigin("https://evil.example", "robot.local"));
  EXPECT_FALSE(SameOrigin("null", "robot.local"));
  EXPECT_FALSE(SameOrigin("ftp://robot.local", "robot.local"));
  EXPECT_NE(SessionCookie("id", std::chrono::seconds(60), true).find("; HttpOnly; SameSite=Strict; Secure"),
            std::string::npos);
}

TEST(GateTest, TheLimiterRefusesTheEleventhFailureInAMinuteAndForgetsAfterIt) {
  LoginLimiter limiter(10);
  const auto t0 = std::chrono::steady_clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(limiter.RetryAfter("client", t0 + std::chrono::seconds(i)), 0) << i;
    limiter.Failed("client", t0 + std::chrono::seconds(i));
  }
  EXPECT_EQ(limiter.RetryAfter("client", t0 + std::chrono::seconds(10)), 50);
  EXPECT_EQ(limiter.RetryAfter("other", t0 + std::chrono::seconds(10)), 0);
  EXPECT_EQ(limiter.RetryAfter("client", t0 + std::chrono::seconds(61)), 0) << "the first failure is a minute old";
}

TEST_F(AccountsTest, UsersSessionsAndTokens) {
  Accounts accounts(dir_ / "accounts.db");
  EXPECT_EQ(fs::status(dir_ / "accounts.db").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_FALSE(accounts.HasUsers());
  auth::Setup setup(accounts);  // qualified: gtest has a Setup of its own
  const auto code = setup.code();
  ASSERT_TRUE(code.has_value());
  EXPECT_THROW(setup.Complete("WRONG-CODE", "root", "a-long-password"), auth::Setup::SetupError);
  EXPECT_THROW(setup.Complete(*code, "root", "short"), AccountError);
  EXPECT_THROW(setup.Complete(*code, "bad name", "a-long-password"), AccountError);
  EXPECT_EQ(setup.Complete(*code, "root", "a-long-password").role, Role::kAdmin);
  EXPECT_FALSE(setup.code().has_value());
  EXPECT_THROW(setup.Complete(*code, "root2", "a-long-password"), auth::Setup::SetupError);

  EXPECT_TRUE(accounts.CheckPassword("root", "a-long-password").has_value());
  EXPECT_FALSE(accounts.CheckPassword("root", "wrong").has_value());
  EXPECT_FALSE(accounts.CheckPassword("nobody", "a-long-password").has_value());
  EXPECT_THROW(accounts.AddUser("root", "another-password", Role::kViewer), AccountError);
  EXPECT_THROW(accounts.DeleteUser("root"), AccountError) << "the last admin";

  const std::string session = accounts.OpenSession("root", std::chrono::seconds(3600));
  EXPECT_EQ(accounts.Session(session)->name, "root");
  EXPECT_FALSE(accounts.Session(session + "x").has_value());
  const std::string stale = accounts.OpenSession("root", std::chrono::seconds(-1));
  EXPECT_FALSE(accounts.Session(stale).has_value()) << "expired";
  accounts.CloseSession(session);
  EXPECT_FALSE(accounts.Session(session).has_value());

  auto [token, secret] = accounts.CreateToken("fleet", Role::kOperator, "root");
  EXPECT_EQ(accounts.Token(secret)->role, Role::kOperator);
  EXPECT_FALSE(accounts.Tokens().front().last_used.empty());
  EXPECT_TRUE(accounts.RevokeToken(token.id));
  EXPECT_FALSE(accounts.Token(secret).has_value());
  EXPECT_FALSE(accounts.RevokeToken(token.id));

  accounts.AddUser("viewer", "viewer-password", Role::kViewer);
  const std::string viewer_session = accounts.OpenSession("viewer", std::chrono::seconds(3600));
  EXPECT_TRUE(accounts.DeleteUser("viewer"));
  EXPECT_FALSE(accounts.Session(viewer_session).has_value()) << "a deleted user's sessions end";

  for (int i = 0; i < 5; ++i)
    accounts.Audit({"root", "127.0.0.1", "POST", "/api/v1/zones", 201, "z" + std::to_string(i)}, 3);
  const auto log = accounts.AuditLog({.limit = 10});
  ASSERT_EQ(log.size(), 3u) << "only the newest kept";
  EXPECT_EQ(log.back()["detail"], "z4");
  EXPECT_EQ(accounts.AuditLog({.after = log[1]["sequence"].get<std::int64_t>(), .limit = 10}).size(), 1u);
}

// The admin page's filters and pages: by who, by path, failures only, and older pages by `before`.
TEST_F(AccountsTest, TheAuditLogIsFilteredAndPaged) {
  Accounts accounts(dir_ / "corridor.db");
  for (int i = 0; i < 10; ++i) {
    accounts.Audit({i % 2 == 0 ? "alice" : "token:fleet", "127.0.0.1", "POST",
                    i < 5 ? "/api/v1/zones" : "/api/v1/missions", i % 3 == 0 ? 422 : 201, std::to_string(i)});
  }
  const auto details = [](const std::vector<nlohmann::json>& log) {
    std::string out;
    for (const nlohmann::json& r : log) out += r["detail"].get<std::string>();
    return out;
  };
  EXPECT_EQ(details(accounts.AuditLog({})), "0123456789");
  EXPECT_EQ(details(accounts.AuditLog({.who = "alice"})), "02468");
  EXPECT_EQ(details(accounts.AuditLog({.path_contains = "missions"})), "56789");
  EXPECT_EQ(details(accounts.AuditLog({.failed_only = true})), "0369");
  EXPECT_EQ(details(accounts.AuditLog({.who = "token:fleet", .path_contains = "zones"})), "13");
  // Pages of three, newest first: each the three before the oldest of the page after it.
  const auto newest = accounts.AuditLog({.limit = 3});
  EXPECT_EQ(details(newest), "789");
  const auto older = accounts.AuditLog({.before = newest.front()["sequence"].get<std::int64_t>(), .limit = 3});
  EXPECT_EQ(details(older), "456");
  EXPECT_EQ(details(accounts.AuditLog({.before = 2, .limit = 3})), "0");
}

}  // namespace
}  // namespace corridor::server::auth
