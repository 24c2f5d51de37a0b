"""Names of this process's threads (Linux: /proc/self/task/*/comm). The core
names its render threads "gridwalk", its build threads "gridwalk-build" and
the viewport's controller "gridwalk-view", and the workers of a batched
ray query (Scene.intersect / occluded) "gridwalk-rays"."""
import os


def thread_names() -> list[str]:
    names = []
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as f:
                names.append(f.read().strip())
        except (FileNotFoundError, ProcessLookupError):
            # The thread ended meanwhile: its directory is gone, or (between
            # the open and the read) its comm reads as ESRCH.
            pass
    return names
