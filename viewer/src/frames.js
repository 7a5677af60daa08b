// The frames the page steps through and plays: the run frames of the .glb panes (of two runs side
// by side, every frame either kept), the keyframe each pane shows at a run frame (its morph
// target), a jump to a run frame and the playback at the glTF's key times.

/**
 * The run frames the page steps through for its .glb panes and their play times (seconds). Two
 * runs side by side step by run frame: every frame either kept, one keyframe a tick (each pane
 * at its last kept frame at or before it: paneKeyframe). No .glb: frame 0 alone.
 * @returns {{frameNumbers: number[], times: number[]}}
 */
export function frameSteps(glbs) {
  if (glbs.length === 2) {
    const frameNumbers = [...new Set(glbs.flatMap((p) => p.frameNumbers))].sort((a, b) => a - b);
    return { frameNumbers, times: frameNumbers.map((_, k) => k / 24) };
  }
  return { frameNumbers: glbs.length ? glbs[0].frameNumbers : [0], times: glbs.length ? glbs[0].times : [0] };
}

/** The index of the last of the (ascending) frame numbers at or before run frame f; 0 if none. */
export function lastAtOrBefore(frameNumbers, f) {
  let k = 0;
  frameNumbers.forEach((n, i) => { if (n <= f) k = i; });
  return k;
}

/**
 * The keyframe a .glb pane shows at run frame `frame`: its fixed one ("before | after"), else its
 * last kept frame at or before it (the same index when the page steps through this file's frames).
 */
export const paneKeyframe = (p, frame) => (p.fixed !== undefined ? p.fixed : lastAtOrBefore(p.frameNumbers, frame));

/** Sets each .glb pane's morph target influences to its keyframe at run frame `frame`. */
export function showFrame(panes, frame) {
  for (const p of panes) {
    if (p.kind !== 'glb') continue;
    const kp = paneKeyframe(p, frame);
    for (const m of p.meshes) {
      const influences = m.morphTargetInfluences ?? [];
      influences.fill(0);
      if (kp > 0 && kp <= influences.length) influences[kp - 1] = 1;  // the glTF's STEP keyframe kp
    }
  }
}

/**
 * Playback of the page's keyframes (state: {playing, keyframe, times, frameNumbers}) at their key
 * times, wrapping at the end; `setKeyframe(k)` shows keyframe k and `button` says Play or Pause.
 * @returns {(on: boolean) => void} starts or stops it
 */
export function player(state, setKeyframe, button) {
  let playStart = 0, playFrom = 0;
  function tick(now) {
    if (!state.playing) return;
    const t = state.times[playFrom] + (now - playStart) / 1000;
    let k = playFrom;
    while (k + 1 < state.times.length && state.times[k + 1] <= t) k++;
    if (k !== state.keyframe) setKeyframe(k);
    if (k === state.times.length - 1) { playFrom = 0; playStart = now + 500; }
    requestAnimationFrame(tick);
  }
  return (on) => {
    state.playing = on;
    button.textContent = on ? 'Pause' : 'Play';
    if (on) {
      playFrom = state.keyframe === state.frameNumbers.length - 1 ? 0 : state.keyframe;
      playStart = performance.now();
      requestAnimationFrame(tick);
    }
  };
}
