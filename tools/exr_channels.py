#!/usr/bin/env python3
"""Reads an OpenEXR with the reference OpenEXR library (the `OpenEXR` Python bindings, not the
Rust `exr` crate Nimbus writes with) and writes each channel as raw little-endian float32 into a
folder: `<folder>/<channel>.f32`, rows top to bottom, plus `channels.json` (names, size, and the
`software` attribute). Nimbus's tests use it to read `render --format exr` back independently.

    python3 tools/exr_channels.py clouds.exr out_folder
"""
import json
import os
import sys

import numpy as np
import OpenEXR


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    path, folder = sys.argv[1], sys.argv[2]
    os.makedirs(folder, exist_ok=True)
    with OpenEXR.File(path, separate_channels=True) as f:
        software = f.header().get("software")
        channels = f.channels()
        names = sorted(channels)
        shape = None
        for name in names:
            pixels = np.asarray(channels[name].pixels, dtype="<f4")
            shape = pixels.shape
            pixels.tofile(os.path.join(folder, name + ".f32"))
    if isinstance(software, bytes):
        software = software.decode()
    with open(os.path.join(folder, "channels.json"), "w") as out:
        json.dump(
            {
                "channels": names,
                "height": int(shape[0]),
                "width": int(shape[1]),
                "software": software,
                "reader": "OpenEXR " + getattr(OpenEXR, "__version__", "?"),
            },
            out,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
