// The WebSocket stream at /api/v1/stream, reconnecting by itself with a growing delay.

export type StreamStatus = 'up' | 'down';

export class Stream {
  private socket: WebSocket | null = null;
  private retryMs = 250;

  constructor(
    private readonly url: string,
    private readonly topics: string[],
    private readonly onMessage: (topic: string, data: unknown) => void,
    private readonly onStatus: (status: StreamStatus) => void,
  ) {
    this.connect();
  }

  // Sends when connected; returns false when the message could not be sent.
  send(message: object): boolean {
    if (this.socket?.readyState !== WebSocket.OPEN) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }

  private connect(): void {
    const socket = new WebSocket(this.url);
    this.socket = socket;
    socket.onopen = () => {
      this.retryMs = 250;
      socket.send(JSON.stringify({ type: 'subscribe', topics: this.topics }));
      this.onStatus('up');
    };
    socket.onmessage = (event) => {
      const message = JSON.parse(String(event.data)) as { topic?: string; data?: unknown; type?: string };
      if (message.topic !== undefined) this.onMessage(message.topic, message.data);
      else if (message.type === 'error') console.warn('stream error', message);
    };
    socket.onclose = () => {
      this.onStatus('down');
      this.socket = null;
      window.setTimeout(() => this.connect(), this.retryMs);
      this.retryMs = Math.min(this.retryMs * 2, 4000);
    };
    socket.onerror = () => socket.close();
  }
}
