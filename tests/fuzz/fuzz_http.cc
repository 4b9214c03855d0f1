// libFuzzer target: bytes as they arrive on the HTTP port, parsed as the server parses them, then answered through the
// real router and handlers. Input it cannot parse gets a 400 from the server and never reaches the API.
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
  if (ec || !parser.is_done()) {
    parser.put_eof(ec);
    if (ec || !parser.is_done()) return 0;
  }
  fuzz.Answer(parser.release());
  return 0;
}
