#!/usr/bin/env python3
"""m4_size.py MAP THRESHOLDS OBJDIR [--update] - per-module code size from a
GNU ld map file (the input sections kept after --gc-sections), compared with
the committed limits. See m4_size.sh."""
import re
import sys


def parse_map(path, objdir):
    """{module: {text, rodata, data, bss}} for the objects under objdir."""
    sizes = {}
    text = open(path, encoding="utf-8", errors="replace").read()
    start = text.find("Linker script and memory map")
    lines = text[start:].splitlines() if start >= 0 else []
    pending = None  # a section name whose address/size is on the next line
    one_line = re.compile(r"^ (\.[^\s]+)\s+0x[0-9a-fA-F]+\s+0x([0-9a-fA-F]+)\s+(\S+)$")
    name_only = re.compile(r"^ (\.[^\s]+)$")
    rest = re.compile(r"^\s+0x[0-9a-fA-F]+\s+0x([0-9a-fA-F]+)\s+(\S+)$")
    for line in lines:
        m = one_line.match(line)
        if m:
            section, size, obj = m.group(1), int(m.group(2), 16), m.group(3)
            pending = None
        else:
            m = name_only.match(line)
            if m:
                pending = m.group(1)
                continue
            m = rest.match(line)
            if not (m and pending):
                pending = None
                continue
            section, size, obj = pending, int(m.group(1), 16), m.group(2)
            pending = None
        if not obj.startswith(objdir) or not obj.endswith(".o"):
            continue
        module = obj[len(objdir):-2]
        kind = None
        for k in ("text", "rodata", "data", "bss"):
            if section == "." + k or section.startswith("." + k + "."):
                kind = k
        if kind is None:
            continue
        sizes.setdefault(module, {"text": 0, "rodata": 0, "data": 0, "bss": 0})[kind] += size
    return sizes


def read_limits(path):
    limits = {}
    try:
        for line in open(path, encoding="utf-8"):
            line = line.split("#", 1)[0].split()
            if len(line) == 2:
                limits[line[0]] = int(line[1])
    except FileNotFoundError:
        pass
    return limits


def main():
    map_path, limits_path, objdir = sys.argv[1:4]
    update = "--update" in sys.argv[4:]
    sizes = parse_map(map_path, objdir)
    if not sizes:
        print("FAIL size_map (no library object found in %s)" % map_path)
        print("size: 0 passed, 1 failed")
        return 1
    flash = {m: s["text"] + s["rodata"] + s["data"] for m, s in sizes.items()}
    total = sum(flash.values())
    print("     %-14s %7s %7s %7s %7s %7s" % ("module", "text", "rodata", "ram", "flash", "limit"))
    limits = read_limits(limits_path)
    for m in sorted(sizes):
        s = sizes[m]
        print("     %-14s %7d %7d %7d %7d %7s" % (m, s["text"], s["rodata"], s["data"] + s["bss"], flash[m],
                                                 limits.get(m, "-")))
    print("     %-14s %7s %7s %7s %7d %7s" % ("total", "", "", "", total, limits.get("total", "-")))
    if update:
        def limit(n):
            return (int(n * 1.10) + 63) // 64 * 64
        with open(limits_path, "w", encoding="utf-8") as out:
            out.write("# Code size limits in bytes (text + rodata + data) per module of the Cortex-M4\n"
                      "# float build (-Os, --gc-sections), checked by `make size`; written by\n"
                      "# `make size-update` as the measured size + 10%, rounded up to 64 bytes.\n")
            for m in sorted(flash):
                out.write("%-14s %d\n" % (m, limit(flash[m])))
            out.write("%-14s %d\n" % ("total", limit(total)))
        print("     wrote %s" % limits_path)
        limits = read_limits(limits_path)
    passed = failed = 0
    for m in sorted(flash) + ["total"]:
        n = total if m == "total" else flash[m]
        if m not in limits:
            print("FAIL size_%s (%d bytes, no limit: `make size-update` and commit %s)" % (m, n, limits_path))
            failed += 1
        elif n > limits[m]:
            print("FAIL size_%s (%d bytes > limit %d)" % (m, n, limits[m]))
            failed += 1
        else:
            print("ok   size_%s (%d <= %d bytes)" % (m, n, limits[m]))
            passed += 1
    ram = sum(s["data"] + s["bss"] for s in sizes.values())
    if ram:
        print("FAIL size_no_ram (the library has %d bytes of .data/.bss)" % ram)
        failed += 1
    else:
        print("ok   size_no_ram (no .data/.bss in the library)")
        passed += 1
    print("size: %d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
