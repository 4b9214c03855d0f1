// Speech on the face page: each phrase the robot says is fetched as audio the daemon synthesized
// (GET /api/v1/face/speech/{sequence}) and played with WebAudio; the mouth follows its loudness. Without the audio (the
// daemon's voice muted or off, or the browser not yet allowed to play sound), the mouth still moves for about as long
// as the phrase takes to say.
export class Voice {
  onChange: () => void = () => undefined;
  private context: AudioContext | null = null;
  private analyser: AnalyserNode | null = null;
  private samples = new Float32Array(256);
  private until = 0;          // performance.now() when the current phrase ends
  private playing = false;

  // Browsers start audio only after a gesture on the page; a kiosk also may be started with autoplay allowed.
  unlock(): void {
    if (this.context === null) {
      try {
        this.context = new AudioContext();
        this.analyser = this.context.createAnalyser();
        this.analyser.fftSize = 512;
        this.analyser.connect(this.context.destination);
      } catch {
        this.context = null;
      }
    }
    void this.context?.resume();
  }

  say(sequence: number, text: string): void {
    // About 14 characters a second, as espeak-ng speaks at its default rate.
    this.until = performance.now() + 400 + 70 * text.length;
    this.onChange();
    void this.play(sequence);
  }

  speaking(): boolean {
    return this.playing || performance.now() < this.until;
  }

  // The mouth's opening now, 0 .. 1.
  level(): number {
    if (this.playing && this.analyser !== null) {
      this.analyser.getFloatTimeDomainData(this.samples);
      let sum = 0;
      for (const v of this.samples) sum += v * v;
      return Math.min(1, Math.sqrt(sum / this.samples.length) * 6);
    }
    if (performance.now() >= this.until) return 0;
    // Syllables at about 5 a second.
    return 0.25 + 0.25 * Math.abs(Math.sin(performance.now() / 1000 * Math.PI * 5));
  }

  private async play(sequence: number): Promise<void> {
    if (this.context === null || this.analyser === null) this.unlock();
    const context = this.context;
    const analyser = this.analyser;
    if (context === null || analyser === null) return;
    try {
      const res = await fetch(`/api/v1/face/speech/${sequence}`);
      if (!res.ok) return;
      const audio = await context.decodeAudioData(await res.arrayBuffer());
      const source = context.createBufferSource();
      source.buffer = audio;
      source.connect(analyser);
      this.playing = true;
      this.until = performance.now() + audio.duration * 1000;
      source.onended = () => {
        this.playing = false;
        this.onChange();
      };
      source.start();
      this.onChange();
    } catch {
      this.playing = false;
    }
  }
}
