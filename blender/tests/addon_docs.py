"""docs/blender.md against the add-on: its table of settings gives properties.py's defaults,
and its scripting example runs as written."""

import bpy

from addon_helpers import check


def doc_path(addon_dir):
    import os
    return os.path.join(os.path.dirname(os.path.abspath(addon_dir)), "docs", "blender.md")


def doc_section(doc, title):
    """The lines of docs/blender.md's section '## title' (to the next '## ')."""
    lines = doc.split("\n")
    start = lines.index("## " + title) + 1
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("## ")), len(lines))
    return lines[start:end]


def doc_example_runs(addon_dir):
    """The scripting example of docs/blender.md runs as written (its first indented block), in
    the factory scene where it starts (the default cube active), and writes its result."""
    import textwrap
    with open(doc_path(addon_dir)) as f:
        section = doc_section(f.read(), "Scripting and background mode")
    first = next(i for i, line in enumerate(section) if line.startswith("    "))
    end = next((i for i in range(first, len(section))
                if section[i] and not section[i].startswith("    ")), len(section))
    code = textwrap.dedent("\n".join(section[first:end]))
    namespace = {}
    exec(compile(code, "docs/blender.md (Scripting)", "exec"), namespace)
    obj = bpy.context.active_object
    keys = obj.data.shape_keys
    check(obj.shellcontract.status.startswith("ok:") and keys is not None
          and len(keys.key_blocks) > 1 and "except RuntimeError" in code,
          "the scripting example of docs/blender.md runs as written, catching a refusal: " +
          obj.shellcontract.status)


def doc_defaults(addon_dir):
    """docs/blender.md's table of settings gives each one's default as properties.py has it."""
    from shellcontract_blender import properties, runner
    with open(doc_path(addon_dir)) as f:
        section = doc_section(f.read(), "Use")
    header = next(line for line in section if line.startswith("| setting"))
    columns = [c.strip() for c in header.strip("|").split("|")]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in section
            if line.startswith("| ") and line is not header and not line.startswith("| ---")]
    rna = properties.ShellContractSettings.bl_rna.properties
    shown = {}
    for row in rows:
        prop = row[1].strip("`").split(".")[-1]
        shown[prop] = row[columns.index("default")] if "default" in columns else None
    for prop in shown:
        p = rna[prop]
        expected = {"FLOAT": lambda: runner.float32_text(p.default),
                    "INT": lambda: str(p.default),
                    "BOOLEAN": lambda: "on" if p.default else "off",
                    "STRING": lambda: p.default or "empty"}[p.type]()
        check(shown[prop] == expected, "docs/blender.md gives {}'s default as {} ({})".format(
            prop, expected, shown[prop]))
    check(len(shown) == 8, "docs/blender.md's table has the 8 settings of the panel")
