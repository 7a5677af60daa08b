#!/usr/bin/env python3
"""Makes the installable add-on: OUT.zip with shellcontract_blender/ at its root (Edit >
Preferences > Add-ons > Install... takes it as it is).

    python3 blender/make_zip.py [OUT.zip]      (default: shellcontract_blender.zip here)
"""

import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "shellcontract_blender"


def make_zip(out):
    root = os.path.join(HERE, PACKAGE)
    tmp = out + ".tmp"
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name in sorted(os.listdir(root)):
            if name.endswith(".py"):  # no __pycache__ or editor files
                z.write(os.path.join(root, name), PACKAGE + "/" + name)
    os.replace(tmp, out)  # never a half-written zip under the final name
    return out


if __name__ == "__main__":
    print(make_zip(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else PACKAGE + ".zip")))
