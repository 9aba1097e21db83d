"""Where the tests find the real MRCLAM recordings: ../shared/data/mrclam beside the repository,
or beside the folder of the worktree it is checked out in. Absent: the tests skip."""

import os

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Below the folder that holds the repository (or the folder of its worktree).
DATASET6 = os.path.join("shared", "data", "mrclam", "MRCLAM_Dataset6")


def dataset6():
    for up in (os.path.dirname(REPO), os.path.dirname(os.path.dirname(REPO))):
        p = os.path.join(up, DATASET6)
        if os.path.isdir(p):
            return p
    return None
