// Plots over the last minutes, drawn with uPlot from the stream's state (sampled twice a second): the speed commanded
// and measured, the battery, the control loop's latency and rate, how sure localization is, and the daemon's own CPU
// and memory. Each plot keeps kKeptS of samples; the panel may be hidden (a phone's closed sheet): the samples are
// kept and the plots drawn when it shows.
import uPlot from 'uplot';

import type { State } from './api';
import { shown } from './layout';

const kSampleS = 0.5;
const kKeptS = 300;
const kHeightPx = 110;

interface Series { label: string; stroke: string; scale?: string; value: (s: State) => number | null; }
interface PlotSpec { id: string; title: string; scales: Record<string, string>; series: Series[]; }

// Each plot: its series, read off one state; a value that is not known is a gap.
const kPlots: PlotSpec[] = [
  { id: 'speed', title: 'Speed', scales: { y: 'm/s' }, series: [
    { label: 'commanded', stroke: '#58a6ff', value: (s) => s.command.linear_mps },
    { label: 'measured', stroke: '#3fb950', value: (s) => s.velocity.linear_mps },
  ] },
  { id: 'battery', title: 'Battery', scales: { y: '%' }, series: [
    { label: 'charge', stroke: '#d29922', value: (s) => s.battery?.percent ?? null },
  ] },
  { id: 'control', title: 'Control loop', scales: { y: 'ms', rate: 'Hz' }, series: [
    { label: 'frame to command p99', stroke: '#f85149', value: (s) => s.control_latency?.p99_ms ?? null },
    { label: 'rate', stroke: '#8b93a1', scale: 'rate', value: (s) => s.control_latency?.rate_hz ?? null },
  ] },
  { id: 'localization', title: 'Localization', scales: { y: 'on walls', sigma: 'm' }, series: [
    { label: 'scan on walls', stroke: '#3fb950', value: (s) => s.localization?.agreement ?? null },
    { label: 'spread', stroke: '#d29922', scale: 'sigma', value: (s) => s.localization?.sigma_m ?? null },
  ] },
  { id: 'process', title: 'corridord', scales: { y: '% CPU', mb: 'MB' }, series: [
    { label: 'CPU', stroke: '#58a6ff', value: (s) => s.process?.cpu_percent ?? null },
    { label: 'memory', stroke: '#a371f7', scale: 'mb', value: (s) => s.process?.resident_mb ?? null },
  ] },
];

const kAxis = { stroke: '#8b93a1', grid: { stroke: '#2b313b', width: 1 }, ticks: { stroke: '#2b313b', width: 1 } };

export class Plots {
  private readonly times: number[] = [];
  private readonly values: (number | null)[][][] = kPlots.map((p) => p.series.map(() => []));
  private readonly plots: uPlot[] = [];
  private lastSample = -Infinity;

  constructor(private readonly panel: HTMLElement) {
    for (const spec of kPlots) {
      const box = document.createElement('div');
      box.className = 'plot';
      box.dataset.plot = spec.id;
      const heading = document.createElement('h3');
      heading.textContent = spec.title;
      box.append(heading);
      panel.append(box);
      const scaleNames = Object.keys(spec.scales);
      this.plots.push(new uPlot({
        width: this.width(),
        height: kHeightPx,
        legend: { show: true, live: false },
        cursor: { drag: { x: false, y: false } },
        scales: { x: { time: true } },
        axes: [
          { ...kAxis, values: (u, ticks) => ticks.map((t) => `${Math.round(t - (u.data[0].at(-1) ?? t))} s`) },
          ...scaleNames.map((scale, i) => ({ ...kAxis, scale, side: i === 0 ? 3 : 1, label: spec.scales[scale], size: 46,
            grid: { show: i === 0, ...kAxis.grid } })),
        ],
        series: [{}, ...spec.series.map((s) => ({ label: s.label, stroke: s.stroke, width: 1.5, scale: s.scale ?? 'y',
          spanGaps: false }))],
      }, [[], ...spec.series.map(() => [])], box));
    }
    new ResizeObserver(() => this.resize()).observe(panel);
  }

  // Takes a state from the stream; samples it every kSampleS and redraws the plots when they are on screen.
  add(state: State): void {
    const now = Date.now() / 1000;
    if (now - this.lastSample < kSampleS) return;
    this.lastSample = now;
    this.times.push(now);
    kPlots.forEach((spec, p) => spec.series.forEach((s, i) => this.values[p][i].push(s.value(state))));
    while (this.times.length > 0 && now - this.times[0] > kKeptS) {
      this.times.shift();
      for (const series of this.values) for (const v of series) v.shift();
    }
    if (shown(this.panel)) this.draw();
  }

  private draw(): void {
    this.plots.forEach((plot, p) => plot.setData([this.times, ...this.values[p]] as uPlot.AlignedData));
  }

  private width(): number {
    return Math.max(200, this.panel.clientWidth - 8);
  }

  private resize(): void {
    if (!shown(this.panel)) return;
    for (const plot of this.plots) plot.setSize({ width: this.width(), height: kHeightPx });
    this.draw();
  }
}
