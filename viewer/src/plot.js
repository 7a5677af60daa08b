// V/V0 against the frame on a canvas, with a marker at the frame shown.

const PAD = { left: 46, right: 12, top: 12, bottom: 30 };

function niceRange(lo, hi) {
  if (hi - lo < 1e-9) { lo -= 0.05; hi += 0.05; }
  const pad = 0.05 * (hi - lo);
  return [lo - pad, hi + pad];
}

/** About four round tick values (1, 2 or 5 times a power of ten apart) within [lo, hi]. */
export function niceTicks(lo, hi) {
  const raw = (hi - lo) / 4;
  if (!(raw > 0)) return [lo];
  const p = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw);
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) ticks.push(Number(v.toPrecision(12)));
  return ticks;
}

/**
 * Draws the series (log: {frame[], volumeRatio[]}) or, for a summary, its final and minimum
 * V/V0 as lines; `current` is the frame number shown (or undefined).
 */
export function drawPlot(canvas, log, summary, current) {
  const ctx = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height;
  ctx.clearRect(0, 0, w, h);
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, w, h);
  ctx.font = '11px sans-serif';
  let frames = [], ratios = [];
  if (log && log.frame.length > 0) {
    frames = log.frame;
    ratios = log.volumeRatio;
    // The log's rows follow each step: frame 0, V/V0 1 by definition, starts the curve (and the
    // axis, so that frame 0's marker is on the plot).
    if (!frames.includes(0) && Math.min(...frames) > 0) { frames = [0, ...frames]; ratios = [1, ...ratios]; }
  } else if (summary && Number.isFinite(summary.finalVolumeRatio)) {
    const last = Number.isFinite(summary.framesRun) ? summary.framesRun : 1;
    frames = [0, last];
    ratios = [1, summary.finalVolumeRatio];
  } else {
    ctx.fillStyle = '#888';
    ctx.fillText('no run log loaded (--log CSV or --summary JSON)', 10, h / 2);
    return;
  }
  const fMin = Math.min(...frames), fMax = Math.max(...frames, fMin + 1);
  const extra = summary && Number.isFinite(summary.minVolumeRatio) ? [summary.minVolumeRatio] : [];
  const [vMin, vMax] = niceRange(Math.min(...ratios, ...extra), Math.max(...ratios, ...extra));
  const px = (f) => PAD.left + (f - fMin) / (fMax - fMin) * (w - PAD.left - PAD.right);
  const py = (v) => h - PAD.bottom - (v - vMin) / (vMax - vMin) * (h - PAD.top - PAD.bottom);

  // Axes and ticks.
  ctx.strokeStyle = '#999';
  ctx.fillStyle = '#444';
  ctx.beginPath();
  ctx.moveTo(PAD.left, PAD.top);
  ctx.lineTo(PAD.left, h - PAD.bottom);
  ctx.lineTo(w - PAD.right, h - PAD.bottom);
  ctx.stroke();
  for (const v of niceTicks(vMin, vMax)) ctx.fillText(String(v), 4, py(v) + 4);
  for (const f of niceTicks(fMin, fMax).filter(Number.isInteger)) ctx.fillText(String(f), px(f) - 8, h - PAD.bottom + 14);
  ctx.fillText('frame', w - PAD.right - 30, h - 4);

  // The series; a summary's two points (rest and end) as points: a line between them would read
  // as a linear decline the summary does not record.
  ctx.strokeStyle = '#2060c0';
  ctx.lineWidth = 2;
  if (log && log.frame.length > 0) {
    ctx.beginPath();
    frames.forEach((f, i) => (i === 0 ? ctx.moveTo(px(f), py(ratios[i])) : ctx.lineTo(px(f), py(ratios[i]))));
    ctx.stroke();
  } else {
    ctx.fillStyle = '#2060c0';
    frames.forEach((f, i) => { ctx.beginPath(); ctx.arc(px(f), py(ratios[i]), 4, 0, 2 * Math.PI); ctx.fill(); });
    ctx.fillStyle = '#444';
  }
  if (extra.length) {
    ctx.strokeStyle = '#c08020';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(PAD.left, py(extra[0]));
    ctx.lineTo(w - PAD.right, py(extra[0]));
    ctx.stroke();
    ctx.fillText('min', w - PAD.right - 22, py(extra[0]) - 3);
  }

  // The frame shown.
  if (Number.isFinite(current)) {
    ctx.strokeStyle = '#c03030';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(px(current), PAD.top);
    ctx.lineTo(px(current), h - PAD.bottom);
    ctx.stroke();
    const i = log ? frames.indexOf(current) : -1;
    if (i >= 0) {
      ctx.fillStyle = '#c03030';
      ctx.beginPath();
      ctx.arc(px(current), py(ratios[i]), 4, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}
