"""The Target volume and Pressure F-curves as the run's schedules: the run follows the curve the
timeline shows (interpolation, handles, easing, F-curve modifiers), not only its keys."""

import bisect

from . import runner


def fcurve_of(obj, prop):
    """The F-curve of obj.shellcontract.<prop> that plays, or None when not animated.

    Only the active action's F-curve is read, and not when it is muted: Blender does not play a
    muted F-curve. NLA strips are not read (docs/blender.md), so a muted one is not either."""
    ad = obj.animation_data
    if ad is None or ad.action is None:
        return None
    fc = ad.action.fcurves.find("shellcontract." + prop)
    if fc is None or fc.mute or len(fc.keyframe_points) == 0:
        return None
    return fc


def keys_of(fc):
    """The keyframes (timeline frame, value) of an F-curve."""
    return [(kp.co[0], kp.co[1]) for kp in fc.keyframe_points]


def library_curve(pairs):
    """The library's curve through (simulation frame, value) keys (docs/design/keyframes.md,
    src/sim/schedule.cpp): monotone cubic Hermite with the PCHIP slopes, the first and last
    values held outside the keys. A function of the simulation frame."""
    f = [float(p[0]) for p in pairs]
    v = [float(p[1]) for p in pairs]
    m = [0.0] * len(f)
    for i in range(1, len(f) - 1):
        h0, h1 = f[i] - f[i - 1], f[i + 1] - f[i]
        d0, d1 = (v[i] - v[i - 1]) / h0, (v[i + 1] - v[i]) / h1
        if d0 * d1 > 0.0:
            w1, w2 = 2.0 * h1 + h0, h1 + 2.0 * h0
            m[i] = (w1 + w2) / (w1 / d0 + w2 / d1)

    def at(x):
        if x <= f[0]:
            return v[0]
        if x >= f[-1]:
            return v[-1]
        i = min(bisect.bisect_right(f, x) - 1, len(f) - 2)
        h = f[i + 1] - f[i]
        t = (x - f[i]) / h
        y = ((2 * t ** 3 - 3 * t ** 2 + 1) * v[i] + (t ** 3 - 2 * t ** 2 + t) * h * m[i]
             + (-2 * t ** 3 + 3 * t ** 2) * v[i + 1] + (t ** 3 - t ** 2) * h * m[i + 1])
        return min(max(y, min(v[i], v[i + 1])), max(v[i], v[i + 1]))
    return at


def sampled(fc, start, first, frames):
    """(simulation frame, value) of the F-curve at simulation frames first..frames, as the
    timeline shows it at frame start + n (float32, as Blender stores it)."""
    return [(n, float(runner.float32_text(fc.evaluate(start + n))))
            for n in range(first, frames + 1)]


def _follows(fc, pairs, samples):
    """Whether the library's curve through the keys is the F-curve at every sampled frame (to
    float32's rounding): then the keys alone give the run the same values, and the run, and its
    record, are those of the keys (two keys with Blender's default auto-clamped handles are the
    library's smoothstep; so are keys that turn at each key, at equal spacing)."""
    if len(fc.modifiers) > 0:
        return False
    curve = library_curve(pairs)
    return all(abs(curve(n) - v) <= 1e-6 * max(1.0, abs(v)) for n, v in samples)


def _late_key(fc, start, frames, field, last):
    """The warning for a key after the run's last frame (the library's, in the add-on's terms)
    where the run is given the sampled curve, which stops at the last frame."""
    late = [kp.co[0] for kp in fc.keyframe_points if kp.co[0] > start + frames + 0.5]
    if not late:
        return ""
    return ("{}: the key at frame {} comes after the run's last frame {}; the run ends on the way "
            "to it, at {:.4g}".format(field, runner.frame_text(late[0]), start + frames, last))


def target_volume_option(fc, start, frames, warnings):
    """The run's target_volume for the Target volume's F-curve, or AddonError. The keys are
    checked first (the messages name a key). Where the F-curve is not the library's curve
    through them (another interpolation, moved handles, easing, modifiers), the run is given the
    F-curve's value at every simulation frame from the first key on (before it, the run goes
    there from the rest volume, as with keys), checked as the curve; a key after the last frame
    then adds its warning to `warnings`. Where every key comes after the last frame, the whole
    run is before the first key, on the way there from the rest volume: the run is given the
    keys, as the CLI would be, and the library's curve from 1 ends part way, with its warning
    (sampled, the curve is the first key's value held before it: the run went all the way)."""
    text = runner.target_volume_schedule(keys_of(fc), start)
    pairs = runner.schedule_keys(keys_of(fc), start, "Target volume")
    if pairs[0][0] > frames:
        return text
    samples = sampled(fc, start, min(pairs[0][0], frames), frames)
    if _follows(fc, ([(0, 1.0)] if pairs[0][0] > 0 else []) + pairs, samples):
        return text
    if samples[0][0] == 0 and samples[0][1] != 1.0:
        raise runner.AddonError(
            "Target volume: the curve is {} at frame {} (the scene's start frame); the run starts "
            "at the rest volume, V/V0 = 1, so the curve must be 1 there".format(
                runner.float32_text(samples[0][1]), start))
    for n, v in samples:
        if not (0.0 < v <= runner.MAX_KEYED_VOLUME):
            raise runner.AddonError(
                "Target volume: the curve is {} at frame {} (its handles, interpolation or "
                "modifiers take it there); a keyed Target volume is a V/V0 above 0 and at most "
                "{}".format(runner.float32_text(v), start + n,
                            runner.float32_text(runner.MAX_KEYED_VOLUME)))
    warnings.append(_late_key(fc, start, frames, "Target volume", samples[-1][1]))
    return runner.schedule_text(samples)


def pressure_option(fc, start, frames, warnings):
    """The run's pressure for the Pressure's F-curve, or AddonError (as target_volume_option,
    sampled from frame 0: before its first key the library holds the first key's value)."""
    text = runner.pressure_schedule(keys_of(fc), start)
    pairs = runner.schedule_keys(keys_of(fc), start, "Pressure")
    samples = sampled(fc, start, 0, frames)
    if _follows(fc, pairs, samples):
        return text
    for n, v in samples:
        if not (-runner.MAX_PRESSURE <= v <= runner.MAX_PRESSURE):
            raise runner.AddonError(
                "Pressure: the curve is {} at frame {} (its handles, interpolation or modifiers "
                "take it there); a Pressure is between {} and {}".format(
                    runner.float32_text(v), start + n, runner.float32_text(-runner.MAX_PRESSURE),
                    runner.float32_text(runner.MAX_PRESSURE)))
    warnings.append(_late_key(fc, start, frames, "Pressure", samples[-1][1]))
    return runner.schedule_text(samples)
