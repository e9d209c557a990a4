#!/usr/bin/env python3
"""Print "<type> <md5>" for every .msg and .srv of a message package folder, sorted.

Two jaka_msgs packages speak the same wire types exactly when these lines agree (rospy and
roscpp check only the md5 on the wire). Usage: scripts/msgs_md5.py PACKAGE_DIR [NAME]
"""
import sys
from pathlib import Path

from genmsg import MsgContext, compute_md5, msg_loader


def md5s(folder: Path, package: str = "jaka_msgs") -> dict:
    context = MsgContext.create_default()
    search = {package: [str(folder / "msg")], "std_msgs": ["/usr/share/std_msgs/msg"]}
    found = {}
    for path in sorted((folder / "msg").glob("*.msg")):
        spec = msg_loader.load_msg_from_file(context, str(path), f"{package}/{path.stem}")
        msg_loader.load_depends(context, spec, search)
        found[spec.full_name] = compute_md5(context, spec)
    for path in sorted((folder / "srv").glob("*.srv")):
        spec = msg_loader.load_srv_from_file(context, str(path), f"{package}/{path.stem}")
        msg_loader.load_depends(context, spec, search)
        found[spec.full_name] = compute_md5(context, spec)
    return found


if __name__ == "__main__":
    for name, md5 in sorted(md5s(Path(sys.argv[1]), *sys.argv[2:]).items()):
        print(name, md5)
