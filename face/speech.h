// The robot's voice: short phrases synthesized by espeak-ng (libespeak-ng, Debian's espeak-ng-data voices) into 16-bit
// mono PCM, handed out as WAV files for the face page to play. espeak-ng keeps one global synthesizer per process:
// every Speech shares it, one phrase at a time.
#pragma once

#include <string>

namespace corridor::face {

struct SpeechOptions {
  std::string voice = "en";  // an espeak-ng voice or language name (en, en-us, de, fr, ...)
  int rate_wpm = 160;        // words a minute, 80 to 450
  int pitch = 50;            // 0 to 100
  int volume = 100;          // espeak-ng's amplitude, 0 to 200
};

class Speech {
 public:
  // Starts espeak-ng (once per process) and checks the voice. Throws std::invalid_argument for options out of range or
  // a voice espeak-ng does not have, std::runtime_error if espeak-ng cannot start (its data missing).
  explicit Speech(const SpeechOptions& options = {});

  // `text` said as a WAV file (RIFF, PCM 16-bit mono at sample_rate_hz()). Thread-safe. Throws std::invalid_argument
  // for an empty text, std::runtime_error if the synthesis fails.
  std::string SynthesizeWav(const std::string& text) const;
  int sample_rate_hz() const { return sample_rate_hz_; }

 private:
  SpeechOptions options_;
  int sample_rate_hz_ = 0;
};

}  // namespace corridor::face
