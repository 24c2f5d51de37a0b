"""Reading the tables the benchmark scripts write into markdown (for the tests
that check what those tables measured)."""


def table_rows(md: str, header_start: str) -> list[dict]:
    """The rows of every markdown table whose header line starts with header_start, as dicts."""
    rows, header = [], None
    for line in md.splitlines():
        if line.startswith(header_start):
            header = [c.strip() for c in line.strip("|").split("|")]
        elif header and line.startswith("|---"):
            continue
        elif header and line.startswith("|"):
            rows.append(dict(zip(header, (c.strip() for c in line.strip("|").split("|")))))
        else:
            header = None
    return rows
