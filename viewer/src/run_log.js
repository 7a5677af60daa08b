// The run's V/V0 per frame, from the --log CSV (columns frame, ..., volume_ratio, ...) or the
// --summary JSON (final and minimum V/V0 only).

/** Parses the CSV log; returns {frame: number[], volumeRatio: number[]}. Throws on a bad file. */
export function parseCsvLog(text) {
  const lines = text.split(/\r?\n/).filter((l) => l.trim() !== '');
  if (lines.length === 0) throw new Error('empty CSV log');
  const header = lines[0].split(',').map((h) => h.trim());
  const iFrame = header.indexOf('frame');
  const iRatio = header.indexOf('volume_ratio');
  if (iFrame < 0 || iRatio < 0) throw new Error('the CSV log has no frame or volume_ratio column');
  const frame = [];
  const volumeRatio = [];
  for (let r = 1; r < lines.length; r++) {
    const cells = lines[r].split(',');
    const f = Number(cells[iFrame]);
    const v = Number(cells[iRatio]);
    if (!Number.isFinite(f) || !Number.isFinite(v)) throw new Error(`CSV log line ${r + 1}: not a number`);
    frame.push(f);
    volumeRatio.push(v);
  }
  return { frame, volumeRatio };
}

/** Parses the JSON summary; returns {finalVolumeRatio, minVolumeRatio, framesRun} (some may be undefined). */
export function parseJsonSummary(text) {
  const s = JSON.parse(text);
  return {
    finalVolumeRatio: s.final_volume_ratio,
    minVolumeRatio: s.min_volume_ratio,
    framesRun: s.frames_run,
  };
}

/**
 * V/V0 of the log's row for `frame`, or undefined when the log has no such row; at frame 0, which
 * the CLI's log has no row of (its rows follow each step), 1: the rest volume's by definition.
 */
export function ratioAt(log, frame) {
  if (!log) return undefined;
  const i = log.frame.indexOf(frame);
  if (i < 0 && frame === 0) return 1;
  return i < 0 ? undefined : log.volumeRatio[i];
}
