"""Threads of this process by name (Linux: /proc/self/task/*/comm). The core
names its render threads "gridwalk" and the viewport's controller thread
"gridwalk-view"."""
import os

RENDER = "gridwalk"
VIEWPORT = "gridwalk-view"


def count(name: str) -> int:
    n = 0
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as f:
                n += f.read().strip() == name
        except (FileNotFoundError, ProcessLookupError):   # the thread ended meanwhile
            pass
    return n
