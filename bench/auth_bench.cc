// What access control costs per request and per login (server/auth): the Argon2id hash and check a login pays, the
// token and session look-ups every authenticated request pays.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "server/auth/accounts.h"
#include "server/auth/secrets.h"

namespace {

namespace fs = std::filesystem;
using namespace corridor::server::auth;

// One accounts database for all the benchmarks, in a temporary directory.
Accounts& SharedAccounts() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("corridor-auth-bench-" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }();
  static Accounts accounts(dir / "accounts.db");
  return accounts;
}

void BM_HashPassword(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(HashPassword("a password of some length"));
}
BENCHMARK(BM_HashPassword)->Unit(benchmark::kMillisecond);

void BM_VerifyPassword(benchmark::State& state) {
  const std::string hash = HashPassword("a password of some length");
  for (auto _ : state) benchmark::DoNotOptimize(VerifyPassword(hash, "a password of some length"));
}
BENCHMARK(BM_VerifyPassword)->Unit(benchmark::kMillisecond);

void BM_TokenLookup(benchmark::State& state) {
  Accounts& accounts = SharedAccounts();
  for (int i = 0; i < 100; ++i) accounts.CreateToken("bench-" + std::to_string(i), Role::kOperator, "bench");
  const std::string secret = accounts.CreateToken("bench", Role::kOperator, "bench").second;
  for (auto _ : state) benchmark::DoNotOptimize(accounts.Token(secret));
}
BENCHMARK(BM_TokenLookup)->Unit(benchmark::kMicrosecond);

// A session look-up extends the session at most once a minute (a write, synced): here a read.
void BM_SessionLookup(benchmark::State& state) {
  Accounts& accounts = SharedAccounts();
  if (!accounts.HasUsers()) accounts.AddUser("bench", "bench-password", Role::kAdmin);
  const std::string session = accounts.OpenSession("bench", std::chrono::hours(1));
  for (auto _ : state) benchmark::DoNotOptimize(accounts.Session(session));
}
BENCHMARK(BM_SessionLookup)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
