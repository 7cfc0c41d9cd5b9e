// Rectangle 2 m x 1 m meshed with linear triangles (T3), cut by a V whose two curves start from
// one point of the bottom edge, (1, 0) m: "left_cut" up to (0.5, 1) m and "right_cut" up to
// (1.5, 1) m. Interface lines meeting at a node of the outer boundary are refused
// (fem/tests/gmsh_mesh.rs); "bulk": the three blocks; "bottom", "right", "top", "left".
h = 0.25;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {2, 0, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {1.5, 1, 0, h};
Point(6) = {0.5, 1, 0, h};
Point(7) = {0, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 1};
Line(8) = {2, 6};
Line(9) = {2, 5};
Curve Loop(1) = {1, 8, 6, 7};
Plane Surface(1) = {1};
Curve Loop(2) = {9, 5, -8};
Plane Surface(2) = {2};
Curve Loop(3) = {2, 3, 4, -9};
Plane Surface(3) = {3};
Physical Surface("bulk") = {1, 2, 3};
Physical Curve("left_cut") = {8};
Physical Curve("right_cut") = {9};
Physical Curve("bottom") = {1, 2};
Physical Curve("right") = {3};
Physical Curve("top") = {4, 5, 6};
Physical Curve("left") = {7};
