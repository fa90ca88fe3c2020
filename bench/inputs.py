"""The inputs the Python benches share: generated families (made once per work folder) and the
meshes of ../shared/data (skipped when absent)."""
import os
import shutil
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


def gmsh_multimaterial(work, clmax=0.016):
    """bench/data/gmsh_multimaterial.geo meshed by Debian's gmsh into WORK (once), its path, or None
    without gmsh. 20 materials, curved interfaces and junction curves; 1.13M tets at 0.016."""
    path = os.path.join(work, f"gmsh_multimaterial_{clmax}.msh")
    if not os.path.exists(path):
        if shutil.which("gmsh") is None:
            return None
        os.makedirs(work, exist_ok=True)
        geo = os.path.join(HERE, "data", "gmsh_multimaterial.geo")
        subprocess.run(["gmsh", geo, "-3", "-clmax", str(clmax), "-nt", "1", "-format", "msh41", "-o", path + ".part"],
                       check=True, stdout=subprocess.DEVNULL)
        os.replace(path + ".part", path)
    return path
