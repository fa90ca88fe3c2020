// A ball inside a box (two volumes = two materials), a sheet and a wire embedded in the box
// volume, with physical groups. Used by tests/unit_io.cpp: the mesh is coarse so that
// `gmsh -3` runs in well under a second; gmsh_sphere_in_box.msh is its committed output.
SetFactory("OpenCASCADE");
Mesh.MeshSizeMax = 0.35;

Box(1) = {0, 0, 0, 2, 2, 2};
Sphere(2) = {0.9, 1, 1, 0.45};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
e = 1e-3;
ball() = Volume In BoundingBox{0.45 - e, 0.55 - e, 0.55 - e, 1.35 + e, 1.45 + e, 1.45 + e};
all() = Volume In BoundingBox{-e, -e, -e, 2 + e, 2 + e, 2 + e};
shell() = all();
shell() -= ball();
sphere() = Surface In BoundingBox{0.45 - e, 0.55 - e, 0.55 - e, 1.35 + e, 1.45 + e, 1.45 + e};
box() = Surface In BoundingBox{-e, -e, -e, 2 + e, 2 + e, 2 + e};
box() -= sphere();

// The embedded sheet (in the plane z = 0.6) and wire, away from the ball.
Rectangle(100) = {1.5, 0.4, 0.6, 0.3, 0.8};
Point(200) = {0.3, 0.3, 0.3};
Point(201) = {0.3, 1.7, 1.7};
Line(200) = {200, 201};
Surface{100} In Volume{shell(0)};
Curve{200} In Volume{shell(0)};

Physical Volume("shell", 1) = {shell()};
Physical Volume("ball", 2) = {ball()};
Physical Surface("box_boundary", 3) = {box()};
Physical Surface("sphere", 4) = {sphere()};
Physical Surface("sheet", 5) = {100};
Physical Curve("wire", 6) = {200};
Physical Point("wire_ends", 7) = {200, 201};
