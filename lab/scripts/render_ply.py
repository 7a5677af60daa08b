#!/usr/bin/python3
"""Renders a mesh written by shellcontract (a `regions` PLY with per-face colours, a `--fields`
PLY with per-vertex colours, or an OFF/OBJ) to a PNG. Kept under this name for the commands in
the docs; the work is done by lab/scripts/render_mesh.py (a z-buffer rasterizer that takes the up
axis from the mesh), whose options it accepts.

Usage: lab/scripts/render_ply.py IN.ply OUT.png [--up auto|x|y|z|-x|-y|-z] [--azim 30] [--elev 15]
                             [--size 800x600] [--title TEXT]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_mesh  # noqa: E402

if __name__ == "__main__":
    sys.exit(render_mesh.main())
