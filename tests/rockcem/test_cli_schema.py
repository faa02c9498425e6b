"""`rockcem schema`: every scene key in aligned columns."""

from rockcem import cli
from rockcem.scene import SCHEMA


def test_schema_columns_line_up(capsys):
    """The word 'default' and the description start at one column on every key line, however
    long a unit or default is (a long one used to run into the next column)."""
    assert cli.main(["schema"]) == 0
    out = capsys.readouterr().out
    section, lines = None, []
    for ln in out.splitlines():
        if ln == "(top level)":
            section = "scene"
        elif ln.startswith("[") and ln.strip("[]") in SCHEMA:
            section = ln.strip("[]")
        elif ln.startswith("MD scenes"):
            break
        elif section and ln.startswith("  ") and ln.split()[0] in SCHEMA[section]:
            lines.append((ln, SCHEMA[section][ln.split()[0]][3]))
    assert len(lines) == sum(len(s) for s in SCHEMA.values())
    assert len({ln.index(" default ") for ln, _ in lines}) == 1
    assert all(ln.endswith(doc) for ln, doc in lines)
    assert len({len(ln) - len(doc) for ln, doc in lines}) == 1
