// The Spray tool's chart of the spacing search: δ and E against every spacing tried.
import { num } from '../app/format.js';

/**
 * δ (%) and E (µm) against spacing (mm) from SprayPlan.iterations(): two y axes, dashed limit
 * lines; full-resolution figures as filled marks joined by solid lines, the coarse screening
 * as hollow marks joined by thin dotted lines; a ▲ under each spacing that meets the limits;
 * the chosen spacing marked.
 */
export function renderChart(svg, iterations, chosen, limits, mm, um) {
  const W = 380;
  const H = 190;
  const m = { l: 44, r: 44, t: 14, b: 34 };
  const its = [...iterations].sort((a, b) => a.spacing - b.spacing);
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
  if (its.length === 0) {
    svg.innerHTML = '';
    return;
  }
  const xs = its.map((it) => it.spacing * mm);
  const ds = its.map((it) => it.error * 100);
  const es = its.map((it) => it.stdDev * um);
  const dLimit = limits ? limits.maxError * 100 : null;
  const eLimit = limits ? limits.maxStdDev * um : null;
  const xMin = Math.min(...xs);
  const xMax = Math.max(...xs);
  const dMax = Math.max(...ds, dLimit ?? 0) * 1.1 || 1;
  const eMax = Math.max(...es, eLimit ?? 0) * 1.1 || 1;
  const x = (v) => m.l + (xMax > xMin ? ((v - xMin) / (xMax - xMin)) * (W - m.l - m.r) : (W - m.l - m.r) / 2);
  const yd = (v) => H - m.b - (v / dMax) * (H - m.t - m.b);
  const ye = (v) => H - m.b - (v / eMax) * (H - m.t - m.b);
  // A polyline through the points of one fidelity (coarse or full), in spacing order.
  const line = (ys, f, full) => ys.map((v, i) => [v, i]).filter(([, i]) => Boolean(its[i].full ?? true) === full)
    .map(([v, i], k) => `${k ? 'L' : 'M'}${x(xs[i]).toFixed(1)},${f(v).toFixed(1)}`).join('');
  const D = '#0072B2';
  const E = '#D55E00';
  const ticks = (max, f, side, color) => [0, 0.5, 1].map((k) => {
    const v = (max / 1.1) * k;
    const tx = side === 'l' ? m.l - 4 : W - m.r + 4;
    return `<text x="${tx}" y="${f(v) + 3}" text-anchor="${side === 'l' ? 'end' : 'start'}" fill="${color}">${num(v, 2)}</text>`;
  }).join('');
  const xt = [xMin, (xMin + xMax) / 2, xMax].map((v) => `<text x="${x(v)}" y="${H - m.b + 14}" text-anchor="middle">${num(v, 3)}</text>`).join('');
  let chosenDrawn = false;
  const dots = its.map((it, i) => {
    const full = it.full ?? true;
    const isChosen = !chosenDrawn && full && Math.abs(it.spacing - chosen) <= 1e-9 * chosen;
    chosenDrawn ||= isChosen;
    const cls = full ? 'full' : 'coarse';
    const px = x(xs[i]);
    return `<circle class="${cls}" cx="${px}" cy="${yd(ds[i])}" r="${full ? 3 : 2.5}" fill="${full ? D : '#fff'}" stroke="${D}"/>` +
      `<rect class="${cls}" x="${px - 3}" y="${ye(es[i]) - 3}" width="6" height="6" fill="${full ? E : '#fff'}" stroke="${E}"/>` +
      (limits && it.met ? `<path class="met" d="M${px.toFixed(1)},${H - m.b - 7}l3.5,6h-7z" fill="#009E73"/>` : '') +
      (isChosen ? `<line x1="${px}" x2="${px}" y1="${m.t}" y2="${H - m.b}" stroke="#1d232a" stroke-width="1"/>` +
        `<text x="${px}" y="${m.t - 3}" text-anchor="middle">chosen</text>` : '');
  }).join('');
  const limitLines = limits
    ? `<line x1="${m.l}" x2="${W - m.r}" y1="${yd(dLimit)}" y2="${yd(dLimit)}" stroke="${D}" stroke-dasharray="4 3"/>` +
      `<line x1="${m.l}" x2="${W - m.r}" y1="${ye(eLimit)}" y2="${ye(eLimit)}" stroke="${E}" stroke-dasharray="4 3"/>`
    : '';
  svg.innerHTML = `<g class="axes" stroke="#9aa3ad"><line x1="${m.l}" x2="${W - m.r}" y1="${H - m.b}" y2="${H - m.b}"/>` +
    `<line x1="${m.l}" x2="${m.l}" y1="${m.t}" y2="${H - m.b}"/><line x1="${W - m.r}" x2="${W - m.r}" y1="${m.t}" y2="${H - m.b}"/></g>` +
    `<g class="labels">${ticks(dMax, yd, 'l', D)}${ticks(eMax, ye, 'r', E)}${xt}` +
    `<text x="${(W) / 2}" y="${H - 4}" text-anchor="middle">pass spacing, mm</text>` +
    `<text x="4" y="${m.t + 2}" fill="${D}">δ %</text><text x="${W - 4}" y="${m.t + 2}" text-anchor="end" fill="${E}">E µm</text></g>` +
    limitLines +
    `<path d="${line(ds, yd, false)}" fill="none" stroke="${D}" stroke-width="0.8" stroke-dasharray="1.5 2"/>` +
    `<path d="${line(es, ye, false)}" fill="none" stroke="${E}" stroke-width="0.8" stroke-dasharray="1.5 2"/>` +
    `<path d="${line(ds, yd, true)}" fill="none" stroke="${D}" stroke-width="1.5"/>` +
    `<path d="${line(es, ye, true)}" fill="none" stroke="${E}" stroke-width="1.5"/>` + dots;
}
