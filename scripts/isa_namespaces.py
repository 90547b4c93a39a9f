#!/usr/bin/env python3
"""Opens every public header's namespaces through SECCHI_ISA (include/secchi/core/config.hpp).

    python3 scripts/isa_namespaces.py [--check]

Rewrites `namespace secchi {` and `namespace secchi::x {` as `namespace secchi::SECCHI_ISA {` and
`namespace secchi::SECCHI_ISA::x {`, and includes core/config.hpp where a header needs it. With
--check it changes nothing and exits 1, listing the headers that are not in that form (ctest
headers_open_the_isa_namespace).
"""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent / "include" / "secchi"
opening = re.compile(r"^(\s*)namespace secchi(::(?!SECCHI_ISA\b)[A-Za-z_:]+)?\s*\{", re.M)
include_line = '#include "secchi/core/config.hpp"\n'


def fixed(path: pathlib.Path, text: str) -> str:
    if path.name == "config.hpp" and path.parent.name == "core":
        return text
    text = opening.sub(lambda m: f"{m.group(1)}namespace secchi::SECCHI_ISA{m.group(2) or ''} {{", text)
    if "namespace secchi::SECCHI_ISA" in text and include_line not in text:
        # before the header's first #include, or else after its opening comment
        first = re.search(r"^#include", text, re.M)
        if first:
            at = first.start()
        else:
            lines = text.splitlines(keepends=True)
            at = len(lines[0])  # after #pragma once
            for line in lines[1:]:
                if not line.startswith("//"):
                    break
                at += len(line)
        text = text[:at] + include_line + text[at:]
    return text


def main() -> int:
    check = "--check" in sys.argv[1:]
    wrong = []
    for path in sorted(root.rglob("*.hpp")):
        text = path.read_text()
        new = fixed(path, text)
        if new != text:
            wrong.append(str(path.relative_to(root.parent.parent)))
            if not check:
                path.write_text(new)
    if check and wrong:
        print("headers not opening secchi's namespace through SECCHI_ISA (run scripts/isa_namespaces.py):")
        print("\n".join("  " + w for w in wrong))
        return 1
    if not check:
        print(f"{len(wrong)} headers rewritten")
    return 0


if __name__ == "__main__":
    sys.exit(main())
