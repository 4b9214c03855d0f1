#include "drivers/hokuyo/scip_protocol.h"

#include <gtest/gtest.h>

#include <string>

namespace corridor::drivers::hokuyo {
namespace {

std::vector<Response> Read(ResponseReader& reader, std::string_view text) {
  std::vector<Response> out;
  reader.Push(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), out);
  return out;
}

// A line with its check character, as the device ends it.
std::string Checked(const std::string& body) { return body + CheckCharacter(body); }

TEST(ScipProtocolTest, CheckCharactersAndNumbersAreTheDocumentsOwn) {
  EXPECT_EQ(CheckCharacter("00"), 'P');   // "00P": done
  EXPECT_EQ(CheckCharacter("99"), 'b');   // "99b": a streamed scan
  EXPECT_EQ(DecodeNumber("CB"), 1234u);   // the document's 2-character example
  EXPECT_EQ(DecodeNumber("1Dh"), 5432u);  // and its 3-character one
  EXPECT_EQ(DecodeNumber("m2@0"), 16000000u);
  EXPECT_FALSE(DecodeNumber("1D\x7f"));
  EXPECT_EQ(EncodeMd(44, 725), "MD0044072501000\n");
  EXPECT_EQ(EncodeMd(0, 1080, 3, 1, 5), "MD0000108003105\n");
}

TEST(ScipProtocolTest, ParametersAreReadFromTheirLines) {
  const auto line = [](const std::string& body) { return body + ";" + CheckCharacter(body) + "\n"; };
  const std::string pp = "PP\n00P\n" + line("MODL:URG-04LX") + line("DMIN:20") + line("DMAX:5600") + line("ARES:1024") +
                         line("AMIN:44") + line("AMAX:725") + line("AFRT:384") + line("SCAN:600") + "\n";
  ResponseReader reader;
  const std::vector<Response> answers = Read(reader, pp);
  ASSERT_EQ(answers.size(), 1u);
  const std::optional<Parameters> p = DecodeParameters(answers[0]);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->model, "URG-04LX");
  EXPECT_EQ(p->min_range_mm, 20);
  EXPECT_EQ(p->max_range_mm, 5600);
  EXPECT_EQ(p->steps_per_turn, 1024);
  EXPECT_EQ(p->first_step, 44);
  EXPECT_EQ(p->last_step, 725);
  EXPECT_EQ(p->front_step, 384);
  EXPECT_EQ(p->scan_rpm, 600);
  // A missing parameter: no parameters.
  const std::vector<Response> short_answer = Read(reader, "PP\n00P\n" + line("MODL:X") + line("DMIN:20") + "\n");
  ASSERT_EQ(short_answer.size(), 1u);
  EXPECT_FALSE(DecodeParameters(short_answer[0]));
}

// A streamed scan of `ranges` (mm) as the device sends it: echo, 99b, time stamp, data in lines of 64.
std::string ScanText(const std::vector<std::uint32_t>& ranges, std::uint32_t stamp_ms) {
  const auto chars = [](std::uint32_t v, int width) {
    std::string s(static_cast<std::size_t>(width), '0');
    for (int i = width - 1; i >= 0; --i, v >>= 6) s[static_cast<std::size_t>(i)] = static_cast<char>((v & 0x3F) + 0x30);
    return s;
  };
  std::string data;
  for (const std::uint32_t r : ranges) data += chars(r, 3);
  std::string text = "MD0044072501000\n99b\n" + Checked(chars(stamp_ms, 4)) + "\n";
  for (std::size_t at = 0; at < data.size(); at += 64) text += Checked(data.substr(at, 64)) + "\n";
  return text + "\n";
}

TEST(ScipProtocolTest, AScanIsReadAcrossItsLinesWhereverTheReadsEnd) {
  std::vector<std::uint32_t> ranges;
  for (std::uint32_t i = 0; i < 682; ++i) ranges.push_back(20 + i * 7);  // a URG-04LX's 44..725
  const std::string text = ScanText(ranges, 123456);
  ResponseReader reader;
  std::vector<Response> answers;
  for (std::size_t at = 0; at < text.size(); at += 37) {
    const std::string piece = text.substr(at, 37);
    reader.Push(std::span(reinterpret_cast<const std::uint8_t*>(piece.data()), piece.size()), answers);
  }
  ASSERT_EQ(answers.size(), 1u);
  const std::optional<ScanData> scan = DecodeScan(answers[0]);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->timestamp_ms, 123456u);
  EXPECT_EQ(scan->ranges_mm, ranges);
  EXPECT_EQ(reader.dropped(), 0u);
}

TEST(ScipProtocolTest, ABadCheckCharacterOrALostByteCostsThatScanOnly) {
  const std::vector<std::uint32_t> ranges(100, 1500);
  std::string bad = ScanText(ranges, 1);
  bad[bad.find("99b\n") + 12] ^= 0x01;  // a data character changed
  std::string lost = ScanText(ranges, 2);
  lost.erase(lost.size() / 2, 1);
  ResponseReader reader;
  const std::vector<Response> answers =
      Read(reader, "\x13\x7f noise" + bad + lost + ScanText(ranges, 3) + "QT\n00P\n\n");
  ASSERT_EQ(answers.size(), 2u);  // the good scan, and QT's answer after it
  EXPECT_EQ(DecodeScan(answers[0])->timestamp_ms, 3u);
  EXPECT_EQ(answers[1].echo, "QT");
  EXPECT_EQ(answers[1].status, "00");
  EXPECT_GE(reader.dropped(), 2u);
  // Garbage without a line end is dropped whole, and the next answer is read.
  EXPECT_EQ(Read(reader, std::string(500, 'x').append("\n\nBM\n00P\n\n")).size(), 1u);
}

}  // namespace
}  // namespace corridor::drivers::hokuyo
