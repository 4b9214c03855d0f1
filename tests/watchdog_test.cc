// corridord under a stand-in for systemd: a NOTIFY_SOCKET reader sees READY=1 once the API answers and WATCHDOG=1
// pings while the control loop runs, and sees the pings stop when the control loop stalls (the simulator's
// control_stalled fault), which is when systemd (WatchdogSec=) kills and restarts the daemon.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string Output(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buffer[256];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr) out += buffer;
  pclose(pipe);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

// The messages the daemon sends to NOTIFY_SOCKET.
class NotifyReader {
 public:
  explicit NotifyReader(const fs::path& path) : path_(path) {
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", path.c_str());
    if (bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) ADD_FAILURE() << "bind " << path;
  }
  ~NotifyReader() { close(fd_); }

  // Every message that arrives within `within`.
  std::vector<std::string> Read(std::chrono::milliseconds within) const {
    std::vector<std::string> out;
    const auto end = Clock::now() + within;
    while (Clock::now() < end) {
      pollfd p{fd_, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      if (poll(&p, 1, static_cast<int>(std::max<long>(left, 0))) <= 0) continue;
      char buffer[1024];
      const ssize_t n = recv(fd_, buffer, sizeof(buffer), 0);
      if (n > 0) out.emplace_back(buffer, static_cast<std::size_t>(n));
    }
    return out;
  }

 private:
  fs::path path_;
  int fd_ = -1;
};

int Count(const std::vector<std::string>& messages, const std::string& what) {
  int n = 0;
  for (const std::string& m : messages) n += m.find(what) != std::string::npos ? 1 : 0;
  return n;
}

// PUT /api/v1/sim/faults with `body`; returns the response's status line.
std::string PutFaults(int port, const std::string& token, const std::string& body) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return "cannot connect";
  }
  const std::string request = "PUT /api/v1/sim/faults HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " + token +
                              "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                              "\r\nConnection: close\r\n\r\n" + body;
  if (write(fd, request.data(), request.size()) != static_cast<ssize_t>(request.size())) {
    close(fd);
    return "cannot send";
  }
  std::string response;
  char buffer[512];
  for (ssize_t n; (n = read(fd, buffer, sizeof(buffer))) > 0;) response.append(buffer, static_cast<std::size_t>(n));
  close(fd);
  return response.substr(0, response.find("\r\n"));
}

TEST(WatchdogTest, PingsStopWhenTheControlLoopStallsAndResumeAfter) {
  const fs::path dir = fs::temp_directory_path() / ("corridor-watchdog-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string token =
      Output(std::string(CORRIDORD) + " token create --role operator --name watchdog --state-dir " + dir.string() +
             " 2>/dev/null");
  ASSERT_EQ(token.rfind("cor_", 0), 0u) << token;
  NotifyReader reader(dir / "notify.sock");

  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("NOTIFY_SOCKET", (dir / "notify.sock").c_str(), 1);
    setenv("WATCHDOG_USEC", "400000", 1);  // a ping every 200 ms
    const std::string config = std::string(CORRIDOR_SOURCE_DIR) + "/config/corridor.yaml";
    const std::string log = (dir / "corridord.log").string();
    freopen(log.c_str(), "w", stderr);
    execl(CORRIDORD, CORRIDORD, "--config", config.c_str(), "--port", "0", "--state-dir", dir.c_str(), nullptr);
    _exit(127);
  }

  // READY=1 once it listens, with the port in its status.
  int port = 0;
  for (const auto end = Clock::now() + std::chrono::seconds(30); port == 0 && Clock::now() < end;) {
    for (const std::string& m : reader.Read(std::chrono::milliseconds(200))) {
      std::smatch match;
      if (m.find("READY=1") != std::string::npos && std::regex_search(m, match, std::regex("port (\\d+)"))) {
        port = std::stoi(match[1]);
      }
    }
  }
  ASSERT_GT(port, 0) << "no READY=1";

  EXPECT_GE(Count(reader.Read(std::chrono::milliseconds(1500)), "WATCHDOG=1"), 5) << "pings while running";
  EXPECT_EQ(PutFaults(port, token, R"({"control_stalled": true})"), "HTTP/1.1 200 OK");
  reader.Read(std::chrono::milliseconds(300));  // one ping may be on its way
  EXPECT_EQ(Count(reader.Read(std::chrono::milliseconds(1500)), "WATCHDOG=1"), 0) << "pings while stalled";
  EXPECT_EQ(PutFaults(port, token, R"({"control_stalled": false})"), "HTTP/1.1 200 OK");
  EXPECT_GE(Count(reader.Read(std::chrono::milliseconds(1500)), "WATCHDOG=1"), 4) << "pings after the stall";

  kill(pid, SIGTERM);
  const auto stopping = reader.Read(std::chrono::milliseconds(500));
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "status " << status << "\n"
      << Output("tail -c 3000 " + (dir / "corridord.log").string());
  EXPECT_GE(Count(stopping, "STOPPING=1"), 1);
  fs::remove_all(dir);
}

}  // namespace
