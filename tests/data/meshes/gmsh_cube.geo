// Unit cube, coarse, for Tactus's reader tests: physical surface 1 (all faces), volume 7.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Surface(1) = {1, 2, 3, 4, 5, 6};
Physical Volume(7) = {1};
Mesh.MeshSizeMax = 1.0;
