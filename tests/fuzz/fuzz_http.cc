// libFuzzer target: bytes as they arrive on the HTTP port, parsed as the server parses them, then answered through the
// real router and handlers. Input it cannot parse gets a 400 from the server and never reaches the API. A request
// with credentials (Authorization, Cookie) or an Origin comes from the network, so the access gate reads them; the
// others come from a trusted caller, so the handlers behind the gate are reached.
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http.hpp>

#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_graph.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace http = boost::beast::http;
  auto& fuzz = corridor::fuzz::FuzzGraph::Get();
  http::request_parser<http::string_body> parser;
  parser.body_limit(static_cast<std::uint64_t>(fuzz.graph().config().server.max_body_bytes));
  parser.header_limit(16 * 1024);
  boost::beast::error_code ec;
  parser.eager(true);
  parser.put(boost::asio::buffer(data, size), ec);
  if (ec) return 0;  // the server answers 400
  if (!parser.is_done()) {
    // The connection closing after a message without a length. Only after some of it: Beast asserts that much.
    if (!parser.got_some()) return 0;
    parser.put_eof(ec);
    if (ec || !parser.is_done()) return 0;
  }
  const auto request = parser.release();
  const bool credentials = request.count(http::field::authorization) > 0 || request.count(http::field::cookie) > 0 ||
                           request.count(http::field::origin) > 0;
  if (credentials) {
    fuzz.Answer(request, corridor::server::Caller{"192.0.2.7", false, false});
  } else {
    fuzz.Answer(request);
  }
  return 0;
}
