"""Threads of this process by name (Linux: /proc/self/task/*/comm). The core
names its render threads "gridwalk" and the viewport's controller thread
"gridwalk-view"."""
import os

RENDER = "gridwalk"
VIEWPORT = "gridwalk-view"


def names() -> list[str]:
    """The names of this process's threads that are still running."""
    out = []
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as f:
                out.append(f.read().strip())
        except (FileNotFoundError, ProcessLookupError):   # the thread ended meanwhile
            pass
    return out


def count(name: str) -> int:
    return names().count(name)
