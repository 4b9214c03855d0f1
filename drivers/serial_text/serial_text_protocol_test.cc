#include "drivers/serial_text/serial_text_protocol.h"

#include <gtest/gtest.h>

#include <string>

namespace corridor::drivers::serial_text {
namespace {

std::vector<std::string> Split(LineSplitter& splitter, std::string_view text, int* overlong = nullptr) {
  std::vector<std::string> lines;
  const int dropped = splitter.Push(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), lines);
  if (overlong) *overlong = dropped;
  return lines;
}

TEST(SerialTextProtocolTest, CommandsAreTheLettersAndNumbersTheBoardReads) {
  EXPECT_EQ(kReadEncoders, "e\r");
  EXPECT_EQ(EncodeMotorSpeeds(12, -7), "m 12 -7\r");
  EXPECT_EQ(EncodeMotorSpeeds(0, 0), "m 0 0\r");
}

TEST(SerialTextProtocolTest, AnswersAreCutIntoLinesWhereverTheReadsEnd) {
  LineSplitter splitter;
  EXPECT_TRUE(Split(splitter, "123 -4").empty());
  EXPECT_EQ(Split(splitter, "5\r\nOK\r\n9"), (std::vector<std::string>{"123 -45", "OK"}));
  EXPECT_EQ(Split(splitter, "0 1\n"), (std::vector<std::string>{"90 1"}));  // LF alone ends a line too
  // A run of garbage longer than any answer is dropped whole, and the next line is read.
  int overlong = 0;
  EXPECT_EQ(Split(splitter, std::string(100, '\x55') + "\r\n7 8\r\n", &overlong), (std::vector<std::string>{"7 8"}));
  EXPECT_EQ(overlong, 1);
}

TEST(SerialTextProtocolTest, OnlyTwoWholeCountsAreAnEncoderReading) {
  ASSERT_TRUE(ParseEncoders("1234 -56"));
  EXPECT_EQ(ParseEncoders("1234 -56")->left, 1234);
  EXPECT_EQ(ParseEncoders("1234 -56")->right, -56);
  EXPECT_EQ(ParseEncoders("-2147483648 2147483647")->left, -2147483648);
  for (const char* line : {"OK", "Invalid Command", "57600", "", " ", "12 ", " 12", "1 2 3", "12a 4", "12  4", "+12 4",
                           "4294967296 0", "1.5 2", "\x55\xAA 3"}) {
    EXPECT_FALSE(ParseEncoders(line)) << '"' << line << '"';
  }
}

TEST(SerialTextProtocolTest, ThirtyTwoBitCountsChangeAcrossTheirWrapEitherWay) {
  EXPECT_EQ(CountsChange(10, 25), 15);
  EXPECT_EQ(CountsChange(25, 10), -15);
  EXPECT_EQ(CountsChange(2147483600, -2147483600), 96);
  EXPECT_EQ(CountsChange(-2147483600, 2147483600), -96);
}

}  // namespace
}  // namespace corridor::drivers::serial_text
