"""Prints where this interpreter looks for packages under a prefix, relative
to it: its site directory under the prefix (the versioned one when there are
several, e.g. Debian's lib/python3.11/dist-packages, searched under both /usr
and /usr/local), else its site-packages scheme for that prefix."""
import os
import site
import sys
import sysconfig

prefix = os.path.realpath(sys.argv[1])
inside = [
    os.path.relpath(os.path.realpath(p), prefix)
    for p in site.getsitepackages()
    if os.path.realpath(p).startswith(prefix + os.sep)
]
version = "python%d.%d" % sys.version_info[:2]
if inside:
    versioned = [p for p in inside if version in p.split(os.sep) and not p.startswith("local")]
    print((versioned or inside)[0])
else:
    scheme = sysconfig.get_path("purelib", "posix_prefix", vars={"base": prefix, "platbase": prefix})
    print(os.path.relpath(scheme, prefix))
