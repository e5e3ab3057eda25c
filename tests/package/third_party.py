#!/usr/bin/env python3
"""package/third_party: THIRD_PARTY.md names everything the shipped binaries bring in.

    third_party.py LINKED_TXT THIRD_PARTY_MD

LINKED_TXT (written by tests/package/CMakeLists.txt) lists the shipped binaries ("binary PATH": the
CLI, the Open CASCADE plugin, the Python module, those the build has) and what the build links into
them ("link ITEM": imported CMake targets, library files, bare names). Checked:

* every shared library that ldd shows for a binary comes from a Debian package (dpkg -S) that a
  shipped row of THIRD_PARTY.md names, unless it is glibc's or the compiler's;
* every imported target or bare library name is named by a shipped row, every library file's
  Debian package likewise (header-only and static libraries leave nothing for ldd to see);
* a library under an LGPL licence is linked dynamically: when one of its CMake targets is linked,
  one of its packages shows up in ldd, and no file of its packages is linked as an archive (.a).

Shipped rows are the table rows above the heading whose title says "not shipped". Exit 0 when all
hold, 1 naming each library and package without an entry, 0 with "skipped" without ldd or dpkg.
"""
import os
import re
import shutil
import subprocess
import sys

# glibc and the compiler's runtime: part of the toolchain, not third-party libraries we choose.
TOOLCHAIN_PACKAGES = {"libc6", "libgcc-s1", "libstdc++6"}
TOOLCHAIN_NAMES = {"Threads::Threads", "dl", "m", "pthread", "rt"}


def read_entries(md_path):
    """The shipped rows of THIRD_PARTY.md: (name, licence, packages, cmake names) each."""
    rows = []
    columns = None
    lines = open(md_path, encoding="utf-8").read().splitlines()
    for i, line in enumerate(lines):
        if re.match(r"^#+ .*not shipped", line, re.IGNORECASE):
            break
        if not line.startswith("|"):
            columns = None
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if columns is None:
            if i + 1 < len(lines) and re.match(r"^\|[ :|-]+\|?$", lines[i + 1]):
                columns = [c.lower() for c in cells]
            continue
        if re.match(r"^[ :-]+$", cells[0]):
            continue  # the separator row

        def cell(word):
            hits = [k for k, title in enumerate(columns) if word in title]
            return cells[hits[0]] if hits and hits[0] < len(cells) else ""

        ticked = lambda text: set(re.findall(r"`([^`]+)`", text))
        rows.append((cells[0], cell("licen"), ticked(cell("debian")), ticked(cell("cmake"))))
    return rows


def ldd_paths(binary):
    """The shared libraries ldd resolves for BINARY (paths), and the names it cannot find."""
    out = subprocess.run(["ldd", binary], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"FAIL: ldd {binary} exited {out.returncode}: {out.stderr.strip()}")
    paths, missing = [], []
    for line in out.stdout.splitlines():
        m = re.match(r"^\s*(\S+) => (.*) \(0x[0-9a-f]+\)$", line)
        if m:
            paths.append(m.group(2))
        elif "not found" in line:
            missing.append(line.split()[0])
        else:
            m = re.match(r"^\s*(/\S+) \(0x[0-9a-f]+\)$", line)  # the dynamic loader
            if m:
                paths.append(m.group(1))
    return paths, missing


def packages_of(paths):
    """Debian package of each path; /usr-merged paths are asked under both spellings."""
    spellings = {}
    for p in paths:
        real = os.path.realpath(p)
        forms = [p, real]
        for f in (p, real):
            forms.append(f[4:] if f.startswith("/usr/") else "/usr" + f)
        spellings[p] = forms
    asked = sorted({f for forms in spellings.values() for f in forms})
    out = subprocess.run(["dpkg", "-S", *asked], capture_output=True, text=True)
    owner = {}
    for line in out.stdout.splitlines():
        m = re.match(r"^([^/]+): (/.*)$", line)  # "pkg:arch[, pkg2:arch]: /path"
        if m and not line.startswith("diversion"):
            owner[m.group(2)] = m.group(1).split(",")[0].split(":")[0].strip()
    return {p: next((owner[f] for f in forms if f in owner), None) for p, forms in spellings.items()}


def main():
    linked_txt, md_path = sys.argv[1], sys.argv[2]
    if not shutil.which("ldd") or not shutil.which("dpkg"):
        print("ldd or dpkg not found: skipped")
        return 0
    binaries, links = [], []
    for line in open(linked_txt, encoding="utf-8").read().splitlines():
        kind, _, value = line.partition(" ")
        (binaries if kind == "binary" else links).append(value)
    rows = read_entries(md_path)
    listed_packages = set().union(*(r[2] for r in rows)) if rows else set()
    listed_cmake = set().union(*(r[3] for r in rows)) if rows else set()
    problems = []

    shared = {}  # library path -> the binaries that load it
    for b in binaries:
        if not os.path.exists(b):
            problems.append(f"{b} is not built (build the shipped targets before ctest)")
            continue
        paths, missing = ldd_paths(b)
        problems += [f"ldd {os.path.basename(b)}: {name} not found" for name in missing]
        for p in paths:
            shared.setdefault(p, []).append(os.path.basename(b))
    files = [item for item in links if item.startswith("/")]
    owner = packages_of(list(shared) + files)

    loaded_packages = set()
    for p, users in sorted(shared.items()):
        pkg = owner[p]
        loaded_packages.add(pkg)
        if pkg is None:
            problems.append(f"{p} (loaded by {', '.join(users)}) belongs to no Debian package")
        elif pkg not in TOOLCHAIN_PACKAGES and pkg not in listed_packages:
            problems.append(f"{p} (loaded by {', '.join(users)}): Debian package {pkg} has no THIRD_PARTY.md entry")
    for item in links:
        if item in TOOLCHAIN_NAMES:
            continue
        if item.startswith("/"):
            pkg = owner[item]
            if pkg is None:
                problems.append(f"linked file {item} belongs to no Debian package")
            elif pkg not in TOOLCHAIN_PACKAGES and pkg not in listed_packages:
                problems.append(f"linked file {item}: Debian package {pkg} has no THIRD_PARTY.md entry")
        elif item not in listed_cmake:
            problems.append(f"linked CMake target or library {item} has no THIRD_PARTY.md entry")

    # LGPL: a user must be able to swap the library, so it is loaded as a shared object.
    for name, licence, packages, cmake in rows:
        if "LGPL" not in licence or not (cmake & set(links)):
            continue
        if not (packages & loaded_packages):
            problems.append(f"{name} ({licence}) is linked but none of {sorted(packages)} shows in ldd: "
                            "it must be linked dynamically")
        for f in files:
            if owner[f] in packages and f.endswith(".a"):
                problems.append(f"{name} ({licence}) is linked statically: {f}")

    print(f"{len(rows)} shipped entries in THIRD_PARTY.md; {len(binaries)} binaries, "
          f"{len({owner[p] for p in shared})} Debian packages in their ldd, {len(links)} linked items")
    for b in binaries:
        pkgs = sorted({owner[p] or "?" for p, users in shared.items() if os.path.basename(b) in users})
        print(f"  {os.path.basename(b)}: {' '.join(pkgs)}")
    if problems:
        for p in problems:
            print(f"FAIL: {p}", file=sys.stderr)
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
