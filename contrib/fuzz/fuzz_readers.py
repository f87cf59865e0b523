#!/usr/bin/env python3
"""Fuzz forma's input readers: mutate shipped input files and check that
every run either succeeds or fails cleanly (exit code 1, one `error:` line
on stderr, no signal, no hang, a valid failed-run/summary.json).

  contrib/fuzz/fuzz_readers.py BUILD_BIN_DIR [--cases N] [--seed S]
                               [--target NAME] [--timeout SECONDS]

Deterministic for a given seed. Prints one line per finding and a count per
target; exits 1 if anything was found. tests/base/fuzz_readers runs a small
campaign of it in the suite.
"""
import argparse
import json
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))

# name: (app, prm file, file that gets mutated (relative to the prm), extra
# --set assignments that keep a run that still succeeds short[, files from
# the source tree copied next to the prm as (source path, name)[, --set
# assignments of a first run that writes the file]]). A file under out/ is
# put back before every case (each case starts from an empty out/).
TARGETS = {
    "gmsh mesh": ("forma-transient-ipc", "transient_ipc/two_blocks_collision.prm",
                  "meshes/two_blocks_2d.msh", ["Time/End time=0.02"]),
    "obj obstacle": ("forma-transient-ipc", "transient_ipc/ball_in_bowl_3d.prm",
                     "meshes/bowl_3d.obj",
                     ["Time/End time=0.01", "Mesh/Initial refinement=0"]),
    "transient prm": ("forma-transient-ipc",
                      "transient_ipc/two_blocks_collision.prm", None,
                      ["Time/End time=0.02"]),
    "laminate prm": ("forma-laminate", "laminate/hexagon_homogenize.prm", None,
                     ["Grid/Cells along height=24"]),
    "rhombic prm": ("forma-rhombic", "rhombic/homogenize_cell.prm", None, []),
    "png image": ("forma-laminate", "laminate/image_homogenize.prm",
                  "images/round_hole.png", []),
    "pgm image": ("forma-laminate", "laminate/image_homogenize.prm",
                  "images/round_hole.pgm",
                  ["Structure/Image file=images/round_hole.pgm"]),
    "material map": ("forma-rhombic", "rhombic/query_map.prm", "map.json",
                     ["Map/Map file=map.json"],
                     [("contrib/rhombic/map.json", "map.json")]),
    "optimization checkpoint": (
        "forma-contact-assembly", "contact_assembly/connector_stress.prm",
        "out/optimization.checkpoint.json",
        ["Optimization/Max iterations=2", "Optimization/Resume=true",
         "Output/Write vtu=false"],
        [], ["Optimization/Max iterations=1", "Output/Write vtu=false"]),
}

SPECIAL_NUMBERS = ["nan", "inf", "-inf", "-1", "0", "1e308", "-1e308",
                   "4294967297", "99999999999999999999", "1e-320", "-0"]


def mutate(data, rng, kind=None):
    """One random mutation of `data` (bytes), of the given kind or a random
    one."""
    kind = kind or rng.choice(["flip", "junk", "truncate", "number", "number",
                       "line_delete", "line_duplicate", "utf8", "swap",
                       "binary"])
    b = bytearray(data)
    if kind == "flip" and b:
        for _ in range(rng.randint(1, 8)):
            i = rng.randrange(len(b))
            b[i] ^= 1 << rng.randrange(8)
    elif kind == "junk" and b:
        i = rng.randrange(len(b))
        b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
    elif kind == "binary":
        b = bytearray(rng.randrange(256)
                      for _ in range(rng.randint(1, max(1, len(b)))))
    elif kind == "truncate":
        b = b[:rng.randrange(len(b) + 1)]
    elif kind == "number":
        text = b.decode("latin-1")
        numbers = list(re.finditer(r"-?\d+(\.\d+)?(e-?\d+)?", text))
        if numbers:
            m = rng.choice(numbers)
            text = (text[:m.start()] + rng.choice(SPECIAL_NUMBERS) +
                    text[m.end():])
        b = bytearray(text.encode("latin-1"))
    elif kind in ("line_delete", "line_duplicate", "swap"):
        lines = b.split(b"\n")
        if len(lines) > 1:
            i = rng.randrange(len(lines))
            if kind == "line_delete":
                del lines[i]
            elif kind == "line_duplicate":
                lines.insert(i, lines[i])
            else:
                j = rng.randrange(len(lines))
                lines[i], lines[j] = lines[j], lines[i]
        b = bytearray(b"\n".join(lines))
    elif kind == "utf8":
        i = rng.randrange(len(b) + 1)
        b[i:i] = rng.choice([b"\xff\xfe", b"\xc3", b"\xe2\x82", b"\x00",
                             "ν".encode("utf-16"), b"\x1b[31m"])
    return bytes(b), kind


def png_chunks(data):
    """The chunks of a PNG file as [type, data] lists, or None."""
    if not data.startswith(b"\x89PNG\r\n\x1a\n"):
        return None
    chunks, i = [], 8
    while i + 8 <= len(data):
        n = struct.unpack(">I", data[i:i + 4])[0]
        chunks.append([data[i + 4:i + 8], data[i + 8:i + 8 + n]])
        i += 12 + n
    return chunks


def mutate_png(data, rng):
    """A mutation inside a PNG's chunks with valid checksums, so that it
    reaches the decoder: header fields, the compressed or the raw image
    data, a chunk dropped or repeated."""
    chunks = png_chunks(data)
    kind = rng.choice(["header", "header", "deflate", "raw", "raw",
                       "drop_chunk", "repeat_chunk"])
    i = rng.randrange(len(chunks))
    if kind == "header":
        header = bytearray(chunks[0][1])
        field = rng.choice([(0, 4), (4, 4), (8, 1), (9, 1), (10, 1), (11, 1),
                            (12, 1)])
        value = rng.choice([0, 1, 2, 3, 4, 5, 6, 7, 8, 16, 255, 65535,
                            2 ** 31 - 1, 2 ** 32 - 1])
        header[field[0]:field[0] + field[1]] = (
            value % 2 ** (8 * field[1])).to_bytes(field[1], "big")
        chunks[0][1] = bytes(header)
    elif kind in ("deflate", "raw"):
        data_chunks = [c for c in chunks if c[0] == b"IDAT"]
        if data_chunks:
            c = data_chunks[0]
            if kind == "deflate":
                b = bytearray(c[1])
                j = rng.randrange(len(b))
                b[j] ^= 1 << rng.randrange(8)
                c[1] = bytes(b)
            else:
                raw = bytearray(zlib.decompress(c[1]))
                if rng.random() < 0.5 and raw:
                    raw = raw[:rng.randrange(len(raw))]
                else:
                    for _ in range(rng.randint(1, 8)):
                        raw[rng.randrange(len(raw))] = rng.randrange(256)
                c[1] = zlib.compress(bytes(raw))
    elif kind == "drop_chunk":
        del chunks[i]
    else:
        chunks.insert(i, list(chunks[i]))
    out = bytearray(b"\x89PNG\r\n\x1a\n")
    for t, d in chunks:
        out += struct.pack(">I", len(d)) + t + d
        out += struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    return bytes(out), "png " + kind


def run_case(app_path, workdir, prm, extra, timeout):
    args = [app_path, prm, "--set", "Output directory=out"]
    for e in extra:
        args += ["--set", e]
    try:
        p = subprocess.run(args, cwd=workdir, capture_output=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return "hang (over %g s)" % timeout
    stderr = p.stderr.decode("utf-8", "replace")
    if p.returncode == 0:
        return None
    if p.returncode != 1:
        return "exit code %d: %s" % (p.returncode, stderr.strip()[:200])
    error_lines = [l for l in stderr.splitlines() if ": error: " in l]
    if len(error_lines) != 1:
        return "%d error lines: %s" % (len(error_lines), stderr.strip()[:200])
    summary = os.path.join(workdir, "out", "failed-run", "summary.json")
    if os.path.exists(summary):
        try:
            with open(summary, encoding="utf-8") as f:
                json.load(f)
        except (ValueError, UnicodeDecodeError) as e:
            return "invalid failed-run/summary.json: %s" % e
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("bin")
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--target", action="append")
    parser.add_argument("--timeout", type=float, default=60)
    options = parser.parse_args()
    findings = 0
    for name in options.target or sorted(TARGETS):
        app, prm, victim, extra = TARGETS[name][:4]
        copies = TARGETS[name][4] if len(TARGETS[name]) > 4 else []
        prepare = TARGETS[name][5] if len(TARGETS[name]) > 5 else None
        rng = random.Random("%s/%d" % (name, options.seed))
        prm_source = os.path.join(SOURCE, "parameter_files", prm)
        work = tempfile.mkdtemp(prefix="forma-fuzz-")
        shutil.copytree(os.path.dirname(prm_source), work, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("results"))
        for source, copy in copies:
            shutil.copyfile(os.path.join(SOURCE, source),
                            os.path.join(work, copy))
        prm_name = os.path.basename(prm)
        target = os.path.join(work, victim or prm_name)
        if prepare is not None:
            problem = run_case(os.path.join(options.bin, app), work,
                               prm_name, prepare, options.timeout)
            if problem or not os.path.exists(target):
                print("%s: the run that writes %s failed: %s" %
                      (name, victim, problem))
                findings += 1
                continue
        with open(target, "rb") as f:
            original = f.read()
        counts = {"clean failure": 0, "success": 0, "finding": 0}
        for case in range(options.cases):
            # Every campaign starts with a file of random bytes.
            if case > 0 and png_chunks(original) and rng.random() < 0.75:
                data, kind = mutate_png(original, rng)
            else:
                data, kind = mutate(original, rng,
                                    "binary" if case == 0 else None)
            shutil.rmtree(os.path.join(work, "out"), ignore_errors=True)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            with open(target, "wb") as f:
                f.write(data)
            problem = run_case(os.path.join(options.bin, app), work,
                               prm_name, extra, options.timeout)
            if problem:
                counts["finding"] += 1
                findings += 1
                keep = os.path.join(tempfile.gettempdir(),
                                    "forma-fuzz-finding-%s-%d" %
                                    (name.replace(" ", "_"), case))
                with open(keep, "wb") as f:
                    f.write(data)
                print("%s case %d (%s): %s [input kept in %s]" %
                      (name, case, kind, problem, keep))
            elif os.path.exists(os.path.join(work, "out", "summary.json")):
                counts["success"] += 1
            else:
                counts["clean failure"] += 1
        shutil.rmtree(work)
        print("%s: %d cases, %d clean failures, %d runs that still succeed, "
              "%d findings" % (name, options.cases, counts["clean failure"],
                               counts["success"], counts["finding"]))
        sys.stdout.flush()
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
