"""The inputs the Python benches share: generated families (made once per work folder) and the
meshes of ../shared/data (skipped when absent)."""
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "data"))
FAMILIES = ("cube-sphere", "slab", "linked-tori", "polycrystal")


def family(topotet, work, name, tets):
    """`topotet generate NAME --tets TETS` into WORK (once), its path."""
    path = os.path.join(work, f"{name}_{tets}.mesh")
    if not os.path.exists(path):
        os.makedirs(work, exist_ok=True)
        subprocess.run([topotet, "generate", name, "--tets", str(tets), "-o", path, "-q"], check=True,
                       stdout=subprocess.DEVNULL)
    return path


def shared(rel):
    """The path of ../shared/data/REL, or None when this checkout has no such file."""
    path = os.path.join(SHARED, rel)
    return path if os.path.exists(path) else None
