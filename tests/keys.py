"""keys.py - the key table of docs/scene-format.md against the scene parser's own keys.

Every key the parser takes (src/scene_parse.h: rj__sk_solver, rj__sk_link, rj__sk_joint,
rj__sk_load, and the material's and section's subsets of the link's, RJ__SK_MAT_KEYS and
RJ__SK_SEC_KEYS) must have a row in the table of its section, and every key the table
names must be one the parser takes. One PASS or FAIL line per section.
Run from the repository root: python3 tests/keys.py
"""
import re
import sys

PARSER = "src/scene_parse.h"
DOC = "docs/scene-format.md"


def parser_array(text, name):
    """The quoted strings of a char-array initializer: static const char NAME[..][..] = {...};"""
    m = re.search(r"static const char " + name + r"\[[^\]]*\]\[[^\]]*\] = \{(.*?)\};", text, re.S)
    if not m:
        sys.exit("keys.py: no array %s in %s" % (name, PARSER))
    return re.findall(r'"([^"]*)"', m.group(1))


def link_enum(text):
    """The names of the RJ__LK_* enum, in order (their index into rj__sk_link)."""
    m = re.search(r"enum \{\s*(RJ__LK_LENGTH.*?)RJ__LK_N\s*\}", text, re.S)
    return re.findall(r"(RJ__LK_\w+)", m.group(1))


def link_subset(text, macro, link_keys, names):
    """The link keys a RJ__SK_*_KEYS bit mask names."""
    start = text.find("#define " + macro)
    if start < 0:
        sys.exit("keys.py: no macro %s in %s" % (macro, PARSER))
    body = []
    for line in text[start:].splitlines():
        body.append(line)
        if not line.rstrip().endswith("\\"):
            break
    found = re.findall(r"(RJ__LK_\w+)", " ".join(body))
    return {link_keys[names.index(n)] for n in found}


def doc_table(text):
    """{section: set of keys} from the table whose header is | section | key | ..."""
    rows, section, on = {}, None, False
    for line in text.splitlines():
        if line.startswith("| section | key |"):
            on = True
            continue
        if not on:
            continue
        if not line.startswith("|"):
            if rows:
                break
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or cells[0].startswith("---"):
            continue
        if cells[0]:
            section = cells[0]
        rows.setdefault(section, set()).update(re.findall(r"`([A-Za-z_0-9]+)`", cells[1]))
    return rows


def main():
    src = open(PARSER).read()
    doc = doc_table(open(DOC).read())
    link = parser_array(src, "rj__sk_link")
    names = link_enum(src)
    want = {
        "solver": set(parser_array(src, "rj__sk_solver")),
        "link": set(link),
        "joint": set(parser_array(src, "rj__sk_joint")),
        "load": set(parser_array(src, "rj__sk_load")),
        "material": link_subset(src, "RJ__SK_MAT_KEYS", link, names),
        "section": link_subset(src, "RJ__SK_SEC_KEYS", link, names),
    }
    failed = 0
    for section, keys in want.items():
        have = doc.get(section, set())
        missing, extra = sorted(keys - have), sorted(have - keys)
        if missing or extra:
            failed += 1
            print("FAIL keys: %s: %s's table lacks %s and names %s, which the parser does "
                  "not take" % (section, DOC, missing or "none", extra or "none"))
        else:
            print("PASS keys: %s: the %d keys of %s's table are the parser's" %
                  (section, len(keys), DOC))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
