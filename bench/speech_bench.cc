// The robot's voice: how long espeak-ng takes to synthesize the phrases the face says, against how long they last
// (the face node synthesizes on the perception executor, so this is what a phrase holds that executor up).
#include <benchmark/benchmark.h>

#include <string>

#include "face/speech.h"

namespace {

void BM_SynthesizePhrase(benchmark::State& state, const char* text) {
  const corridor::face::Speech speech;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string wav = speech.SynthesizeWav(text);
    bytes = wav.size();
    benchmark::DoNotOptimize(wav.data());
  }
  // Seconds of audio per phrase: 16-bit mono after the 44-byte header.
  state.counters["audio_s"] = static_cast<double>(bytes - 44) / 2.0 / speech.sample_rate_hz();
}

BENCHMARK_CAPTURE(BM_SynthesizePhrase, greeting, "Hello!")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SynthesizePhrase, excuse_me, "Excuse me, may I pass?")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SynthesizePhrase, arrived_at, "I have arrived at the kitchen.")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
