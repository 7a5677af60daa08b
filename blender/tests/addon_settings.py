"""The panel's settings as the run's options: which combinations of target volume and pressure
pass the pressure, the Target volume's refusals and warnings in the panel's terms, and muted
keys."""

import bpy

from addon_helpers import check, refusal, uv_sphere


def pressure_combinations(shellcontract, obj):
    """The pressure goes to the run only where it has an effect or the user asked for it: not
    with a target volume (a number or keys) at its default, which is the library's own."""
    from shellcontract_blender import operator
    s = obj.shellcontract
    default = s.bl_rna.properties["pressure"].default
    library = [o.default for o in shellcontract.options() if o.name == "pressure"]
    check(library and float(library[0]) == default,
          "the Pressure field's default {} is the library's ({}): leaving it out runs the same"
          .format(default, library))
    ctx = bpy.context

    def given(setup):
        obj.animation_data_clear()
        s.target_volume, s.pressure = 0.6, default
        setup()
        return operator.run_options(ctx, obj)

    def key(prop, values):
        for frame, value in values:
            setattr(s, prop, value)
            obj.keyframe_insert("shellcontract." + prop, frame=ctx.scene.frame_start + frame)

    cases = [
        ("target 0.6, default pressure", lambda: None, False),
        ("keyed target, default pressure", lambda: key("target_volume", [(0, 1.0), (20, 0.7)]),
         False),
        ("target off: the pressure decides", lambda: setattr(s, "target_volume", 0.0), True),
        ("target 0.6, pressure set to 8", lambda: setattr(s, "pressure", 8.0),
         True),
        ("target 0.6, keyed pressure",
         lambda: key("pressure", [(0, 4.0), (20, 8.0)]), True),
        ("keyed target and keyed pressure",
         lambda: (key("target_volume", [(0, 1.0), (20, 0.7)]),
                  key("pressure", [(0, 4.0), (20, 8.0)])), True),
        ("target off, keyed pressure", lambda: (key("pressure", [(0, 4.0), (20, 8.0)]),
                                                setattr(s, "target_volume", 0.0)), True),
    ]
    for name, setup, passed in cases:
        options = given(setup)
        check(("pressure" in options) == passed, "{}: pressure {}".format(
            name, "given ({})".format(options.get("pressure")) if passed else "left out"))
    given(lambda: setattr(s, "pressure", 8.0))
    s.frames = 3
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "has no effect" not in s.status,
          "a pressure set off its default with a target volume runs without a warning (it shapes "
          "the way to the target): " + s.status)
    obj.animation_data_clear()
    s.target_volume, s.pressure = 0.6, default


def target_volume_messages(obj):
    """The Target volume's rules, refused before the run in the panel's terms: field names,
    timeline frames, values as Blender shows them (float32 rounded), no CLI syntax."""
    from shellcontract_blender import operator
    s = obj.shellcontract
    start = bpy.context.scene.frame_start

    def cli_free(text):
        return ("target_volume" not in text and "00000" not in text and "0:1" not in text
                and "[0, 1)" not in text)

    obj.animation_data_clear()
    s.frames = 5
    for value in (1.0, 1.2):
        s.target_volume = value
        text = refusal()
        check("Target volume {:g}".format(value) in text and "keyframe" in text and cli_free(text)
              and s.status.startswith("error: "),
              "an unkeyed Target volume {:g} is refused in the panel's terms: {}".format(
                  value, text))
    s.target_volume = 0.6
    obj.keyframe_insert("shellcontract.target_volume", frame=start)
    text = refusal()
    check("Target volume" in text and "frame {}".format(start) in text and " 0.6" in text
          and cli_free(text),
          "a first key other than 1 at the start frame is refused by its timeline frame: " + text)
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (20, 0.0)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    text = refusal()
    check("frame {} is 0".format(start + 20) in text and cli_free(text),
          "a key of 0 is refused by its timeline frame: " + text)
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (10.2, 0.8), (10.4, 0.7)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    text = refusal()
    check("frames {:g} and {:g}".format(start + 10.2, start + 10.4) in text and cli_free(text),
          "two keys on one frame are refused by their timeline frames: " + text)
    # Half frames go to the later frame whatever their parity (round() half to even had put
    # 10.5 and 11.5 on one frame, refused, and 11.5 and 12.5 on 11 and 13). The run itself is
    # given such a curve frame by frame (the library's curve through rounded keys is not the one
    # Blender shows); the keys so rounded are what is checked, and refused, first.
    from shellcontract_blender import curves, runner
    for halves in ((10.5, 11.5), (11.5, 12.5)):
        obj.animation_data_clear()
        for frame, value in ((0, 1.0), (halves[0], 0.8), (halves[1], 0.7)):
            s.target_volume = value
            obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
        fc = obj.animation_data.action.fcurves.find("shellcontract.target_volume")
        keyed = runner.target_volume_schedule(curves.keys_of(fc), start)
        check(keyed == "0:1, {}:0.8, {}:0.7".format(int(halves[0] + 0.5), int(halves[1] + 0.5)),
              "keys at half frames {} go to the later frames: {}".format(halves, keyed))
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (40, 0.6), (80, 0.9)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    check(operator.run_options(bpy.context, obj)["target_volume"] == "0:1, 40:0.6, 80:0.9",
          "the keys go to the run as the values Blender shows: {}".format(
              operator.run_options(bpy.context, obj)["target_volume"]))
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "the key at frame {} comes after the run's last frame {}".format(
              start + 80, start + 5) in s.status and cli_free(s.status),
          "a key after the last frame is warned about in timeline frames: " + s.status)
    obj.animation_data_clear()
    s.target_volume = 0.6


def muted_keys():
    """Keys Blender does not play are not the run's: a muted F-curve of the Target volume leaves
    the field's own value."""
    from shellcontract_blender import operator
    obj = uv_sphere()
    s = obj.shellcontract
    start = bpy.context.scene.frame_start
    for frame, value in ((0, 1.0), (40, 0.6), (80, 0.9)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    s.target_volume = 0.7
    keyed = operator.run_options(bpy.context, obj)["target_volume"]
    check(keyed == "0:1, 40:0.6, 80:0.9", "the keys are read while they play: {}".format(keyed))
    fc = obj.animation_data.action.fcurves.find("shellcontract.target_volume")
    fc.mute = True
    unkeyed = operator.run_options(bpy.context, obj)["target_volume"]
    check(unkeyed == 0.7 or str(unkeyed) == "0.7",
          "a muted F-curve is not read as keys: {!r}".format(unkeyed))
    bpy.data.objects.remove(obj)
