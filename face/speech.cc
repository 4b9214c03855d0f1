#include "face/speech.h"

#include <espeak-ng/speak_lib.h>

#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace corridor::face {
namespace {

std::mutex& SynthMutex() {
  static std::mutex mutex;
  return mutex;
}

// espeak-ng's one synthesizer: started at first use, its sample rate remembered.
int StartEspeak() {
  static const int rate = [] {
    const int r = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr, 0);
    if (r <= 0) throw std::runtime_error("speech: espeak-ng could not start (is espeak-ng-data installed?)");
    return r;
  }();
  return rate;
}

int Collect(short* samples, int count, espeak_EVENT* events) {
  if (samples != nullptr && count > 0 && events != nullptr && events->user_data != nullptr) {
    auto* out = static_cast<std::vector<std::int16_t>*>(events->user_data);
    out->insert(out->end(), samples, samples + count);
  }
  return 0;  // go on
}

void PutLe(std::string& out, std::uint32_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFF));
}

}  // namespace

Speech::Speech(const SpeechOptions& options) : options_(options) {
  if (options.rate_wpm < espeakRATE_MINIMUM || options.rate_wpm > espeakRATE_MAXIMUM || options.pitch < 0 ||
      options.pitch > 100 || options.volume < 0 || options.volume > 200) {
    throw std::invalid_argument("speech: rate_wpm 80-450, pitch 0-100, volume 0-200");
  }
  std::lock_guard lock(SynthMutex());
  sample_rate_hz_ = StartEspeak();
  if (espeak_SetVoiceByName(options.voice.c_str()) != EE_OK) {
    throw std::invalid_argument("speech: espeak-ng has no voice '" + options.voice + "'");
  }
}

std::string Speech::SynthesizeWav(const std::string& text) const {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw std::invalid_argument("speech: nothing to say");
  std::vector<std::int16_t> samples;
  {
    std::lock_guard lock(SynthMutex());
    espeak_SetSynthCallback(Collect);
    if (espeak_SetVoiceByName(options_.voice.c_str()) != EE_OK ||
        espeak_SetParameter(espeakRATE, options_.rate_wpm, 0) != EE_OK ||
        espeak_SetParameter(espeakPITCH, options_.pitch, 0) != EE_OK ||
        espeak_SetParameter(espeakVOLUME, options_.volume, 0) != EE_OK) {
      throw std::runtime_error("speech: espeak-ng refused the voice's settings");
    }
    const espeak_ERROR e =
        espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, &samples);
    if (e != EE_OK || espeak_Synchronize() != EE_OK) throw std::runtime_error("speech: espeak-ng failed to synthesize");
  }
  // A canonical 44-byte WAV header, then the samples (little-endian, as WAV is and this machine is).
  const auto data_bytes = static_cast<std::uint32_t>(samples.size() * sizeof(std::int16_t));
  std::string wav = "RIFF";
  PutLe(wav, 36 + data_bytes, 4);
  wav += "WAVEfmt ";
  PutLe(wav, 16, 4);  // fmt chunk size
  PutLe(wav, 1, 2);   // PCM
  PutLe(wav, 1, 2);   // mono
  PutLe(wav, static_cast<std::uint32_t>(sample_rate_hz_), 4);
  PutLe(wav, static_cast<std::uint32_t>(sample_rate_hz_) * 2, 4);  // bytes a second
  PutLe(wav, 2, 2);                                                // bytes a frame
  PutLe(wav, 16, 2);                                               // bits a sample
  wav += "data";
  PutLe(wav, data_bytes, 4);
  const std::size_t header = wav.size();
  wav.resize(header + data_bytes);
  std::memcpy(wav.data() + header, samples.data(), data_bytes);
  return wav;
}

}  // namespace corridor::face
