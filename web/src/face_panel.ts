// The face from the console: an expression shown for a while, or a phrase said (POST /api/v1/face, as a building
// system would ask), and the face the robot shows now.
import { send } from './api';
import { byId, type Report } from './dom';

export class FacePanel {
  constructor(private readonly report: Report) {
    byId('face-show').addEventListener('click', () => {
      const expression = byId<HTMLSelectElement>('face-expression').value;
      const hold = Number(byId<HTMLInputElement>('face-hold').value) || 5;
      void this.ask({ expression, hold_s: hold }, `showing ${expression} for ${hold} s`);
    });
    byId('face-say-form').addEventListener('submit', (event) => {
      event.preventDefault();
      const say = byId<HTMLInputElement>('face-say');
      if (!say.value.trim()) return;
      void this.ask({ say: say.value.trim() }, `saying "${say.value.trim()}"`).then((ok) => { if (ok) say.value = ''; });
    });
  }

  // The expression the robot shows now (the state's face).
  show(face: string): void {
    byId('face-now').textContent = face;
  }

  private async ask(body: object, done: string): Promise<boolean> {
    try {
      await send('POST', '/api/v1/face', body);
      this.report(done);
      return true;
    } catch (e) {
      this.report(e as Error);
      return false;
    }
  }
}
