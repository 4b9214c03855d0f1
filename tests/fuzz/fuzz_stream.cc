// libFuzzer target: one message from a WebSocket client of /api/v1/stream, through the stream handler. Every message
// gets a reply; a server error (an exception the handler did not foresee) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_graph.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto& fuzz = corridor::fuzz::FuzzGraph::Get();
  std::vector<std::string> subscriptions{"state"};
  // An operator: every message type is open to them.
  static const corridor::server::Identity admin{
      corridor::server::auth::Principal{"fuzz", corridor::server::auth::Role::kOperator, "user", ""}, false};
  const std::string text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json reply = fuzz.graph().api().StreamReply(text, subscriptions, admin);
  if (!reply.is_object() || !reply.contains("type")) fuzz.Fail("a reply without a type", text);
  if (reply["type"] == "error" && reply["status"].get<int>() >= 500) {
    fuzz.Fail("server error: " + corridor::server::Dump(reply), text);
  }
  corridor::server::Dump(reply);  // what the session sends
  for (const std::string& topic : subscriptions) fuzz.graph().api().TopicMessage(topic);
  fuzz.CheckHealthy(text);
  return 0;
}
