// Rectangle 2 m x 1 m meshed with linear triangles (T3), with two interfaces crossing in an X
// (four chains meeting at one node):
// - "interface": y = 0.5 m across the whole width (two lines, split at x = 1 m);
// - "branch": x = 1 m across the whole height (two lines, split at y = 0.5 m);
// - "bulk": the four blocks; "bottom", "right", "top", "left": the outer boundary.
// The crossing's node is split into one copy per sector (docs/meshes.md, "Several chains"); the
// scene tiny-fem-x-junction.toml runs on it (tests/tests/validation/fem_junction.rs).
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {2, 0, 0, h};
Point(4) = {2, 0.5, 0, h};
Point(5) = {2, 1, 0, h};
Point(6) = {1, 1, 0, h};
Point(7) = {0, 1, 0, h};
Point(8) = {0, 0.5, 0, h};
Point(9) = {1, 0.5, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 1};
Line(9) = {8, 9};
Line(10) = {9, 4};
Line(11) = {2, 9};
Line(12) = {9, 6};
Curve Loop(1) = {1, 11, -9, 8};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, -10, -11};
Plane Surface(2) = {2};
Curve Loop(3) = {10, 4, 5, -12};
Plane Surface(3) = {3};
Curve Loop(4) = {9, 12, 6, 7};
Plane Surface(4) = {4};
Physical Surface("bulk") = {1, 2, 3, 4};
Physical Curve("interface") = {9, 10};
Physical Curve("branch") = {11, 12};
Physical Curve("bottom") = {1, 2};
Physical Curve("right") = {3, 4};
Physical Curve("top") = {5, 6};
Physical Curve("left") = {7, 8};
