// A multi-material benchmark mesh made by a real mesher (bench/inputs.py `gmsh_multimaterial`):
// two layers of a unit box holding six spheres, a cylinder and a torus; OpenCASCADE's fragments
// share every interface, and each of the 20 pieces is its own material (physical volume). Curved
// interfaces, thin parts (the torus's tube, the cylinder) and junction curves where three or more
// materials meet: what the guarantees work hardest on.
//   gmsh bench/data/gmsh_multimaterial.geo -3 -clmax 0.016 -nt 1 -format msh41 -o OUT.msh
// (-clmax 0.016: 1,134,893 tets, 195,502 vertices, in 43 s with Debian 12's gmsh 4.11.)
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.5};
Box(2) = {0, 0, 0.5, 1, 1, 0.5};
Sphere(3) = {0.3, 0.3, 0.5, 0.18};
Sphere(4) = {0.7, 0.3, 0.5, 0.15};
Sphere(5) = {0.3, 0.7, 0.3, 0.12};
Sphere(6) = {0.7, 0.7, 0.7, 0.14};
Cylinder(7) = {0.5, 0.5, 0.1, 0, 0, 0.8, 0.06};
Torus(8) = {0.5, 0.5, 0.5, 0.3, 0.04};
Sphere(9) = {0.15, 0.85, 0.85, 0.08};
Sphere(10) = {0.85, 0.15, 0.15, 0.08};
v() = BooleanFragments{ Volume{1:10}; Delete; }{};
For i In {0:#v()-1}
  Physical Volume(i + 1) = {v(i)};
EndFor
Mesh.Algorithm3D = 1;  // Delaunay: the same mesh on every run (HXT differs by a few hundred tets)
