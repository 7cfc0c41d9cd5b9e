// Rectangle 2 m x 1 m meshed with linear triangles (T3), with two interfaces meeting in a T:
// - "interface": y = 0.5 m across the whole width (two lines, split at x = 1 m);
// - "branch": x = 1 m from the junction (1, 0.5) m up to the top;
// - "bulk": the three surfaces; "bottom", "right", "top" (both halves), "left": the outer boundary.
// The junction's node is split into one copy per sector (docs/meshes.md, "Several chains"); the
// scenes tiny-fem-t-junction*.toml run on it (tests/tests/validation/fem_junction.rs).
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.5, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {1, 1, 0, h};
Point(6) = {0, 1, 0, h};
Point(7) = {0, 0.5, 0, h};
Point(8) = {1, 0.5, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 1};
Line(8) = {7, 8};
Line(9) = {8, 3};
Line(10) = {8, 5};
Curve Loop(1) = {1, 2, -9, -8, 7};
Plane Surface(1) = {1};
Curve Loop(2) = {9, 3, 4, -10};
Plane Surface(2) = {2};
Curve Loop(3) = {8, 10, 5, 6};
Plane Surface(3) = {3};
Physical Surface("bulk") = {1, 2, 3};
Physical Curve("interface") = {8, 9};
Physical Curve("branch") = {10};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2, 3};
Physical Curve("top") = {4, 5};
Physical Curve("left") = {6, 7};
