#include "face/speech.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <gtest/gtest.h>

namespace corridor::face {
namespace {

struct Wav {
  int rate = 0;
  int channels = 0;
  int bits = 0;
  std::vector<std::int16_t> samples;
};

std::uint32_t Le(const std::string& s, std::size_t at, int bytes) {
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return v;
}

Wav Parse(const std::string& wav) {
  EXPECT_GE(wav.size(), 44u);
  EXPECT_EQ(wav.substr(0, 4), "RIFF");
  EXPECT_EQ(wav.substr(8, 8), "WAVEfmt ");
  EXPECT_EQ(Le(wav, 4, 4), wav.size() - 8);
  EXPECT_EQ(wav.substr(36, 4), "data");
  Wav w;
  w.channels = static_cast<int>(Le(wav, 22, 2));
  w.rate = static_cast<int>(Le(wav, 24, 4));
  w.bits = static_cast<int>(Le(wav, 34, 2));
  const std::uint32_t bytes = Le(wav, 40, 4);
  EXPECT_EQ(bytes, wav.size() - 44);
  w.samples.resize(bytes / 2);
  std::memcpy(w.samples.data(), wav.data() + 44, bytes);
  return w;
}

double Rms(const std::vector<std::int16_t>& s) {
  double sum = 0.0;
  for (const std::int16_t v : s) sum += static_cast<double>(v) * v;
  return s.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(s.size())) / 32768.0;
}

TEST(SpeechTest, APhraseIsRealAudioOfAPlausibleLengthAndLevel) {
  const Speech speech;
  const Wav w = Parse(speech.SynthesizeWav("Excuse me, may I pass?"));
  EXPECT_EQ(w.channels, 1);
  EXPECT_EQ(w.bits, 16);
  EXPECT_EQ(w.rate, speech.sample_rate_hz());
  const double seconds = static_cast<double>(w.samples.size()) / w.rate;
  EXPECT_GT(seconds, 0.8);  // five words at 160 a minute, about 1.5 s with the pauses
  EXPECT_LT(seconds, 4.0);
  EXPECT_GT(Rms(w.samples), 0.02);  // speech, not silence
}

TEST(SpeechTest, TheVolumeSettingChangesTheLevelAndLongerTextTakesLonger) {
  const Wav quiet = Parse(Speech({.volume = 40}).SynthesizeWav("Hello!"));
  const Wav loud = Parse(Speech({.volume = 160}).SynthesizeWav("Hello!"));
  EXPECT_GT(Rms(loud.samples), 2.0 * Rms(quiet.samples));
  const Wav longer = Parse(Speech().SynthesizeWav("Hello! I have arrived at the kitchen, and I am waiting here."));
  EXPECT_GT(longer.samples.size(), 2 * loud.samples.size());
}

TEST(SpeechTest, RefusesAnUnknownVoiceBadSettingsAndNothingToSay) {
  EXPECT_THROW(Speech({.voice = "klingon-xx"}), std::invalid_argument);
  EXPECT_THROW(Speech({.rate_wpm = 10}), std::invalid_argument);
  EXPECT_THROW(Speech().SynthesizeWav("  "), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::face
