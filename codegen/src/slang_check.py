"""Type-checks HLSL files with Slang's front end (the compiler the `slangpy` wheel ships).

Reads a JSON list `[{"path": ..., "entries": [...]}, ...]` on stdin; loads each file as a Slang
module, finds every named entry point (by its `[shader("...")]` attribute) and links them into
one program. Prints one JSON object per file: `{"path", "ok", "output"}`. Run by
`nimbus_codegen::external`, one process for a whole batch (starting Slang takes a second).
"""

import json
import sys

import slangpy as spy

files = json.load(sys.stdin)
session = spy.Device(type=spy.DeviceType.cpu).slang_session
for index, item in enumerate(files):
    try:
        with open(item["path"], encoding="utf-8") as f:
            source = f.read()
        module = session.load_module_from_source(f"nimbus_check_{index}", source)
        entries = [module.entry_point(name) for name in item["entries"]]
        session.link_program([module], entries)
        result = {"path": item["path"], "ok": True, "output": ""}
    except Exception as error:  # Slang reports every diagnostic in the exception's text.
        result = {"path": item["path"], "ok": False, "output": str(error)}
    print(json.dumps(result), flush=True)
