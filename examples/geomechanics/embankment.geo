// The embankment of embankment-mesh.toml for Gmsh: a 24 m x 4 m foundation and, on it, the half embankment
// from the centre line x = 0 (crest to x = 1 m, toe at x = 9 m, 4 m high), sharing the line y = 4 between
// x = 0 and 9 m so that their meshes meet node to node. Two physical groups name the regions, which the scene
// gives materials. Meshed with 0.5 m triangles into embankment.msh:  gmsh -2 embankment.geo
size = 0.5;
Point(1) = {0, 0, 0, size};
Point(2) = {24, 0, 0, size};
Point(3) = {24, 4, 0, size};
Point(4) = {9, 4, 0, size};
Point(5) = {0, 4, 0, size};
Point(6) = {1, 8, 0, size};
Point(7) = {0, 8, 0, size};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Line(6) = {4, 6};
Line(7) = {6, 7};
Line(8) = {7, 5};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {-4, 6, 7, 8};
Plane Surface(2) = {2};
Physical Surface("foundation") = {1};
Physical Surface("embankment") = {2};
