// Rectangle 2 m x 1 m meshed with linear triangles (T3), with an interface along y = 0.5 m made
// of two physical curves, so that a scene can give each its own cohesive law:
// - "weak": 0 <= x <= 1 m, "strong": 1 <= x <= 2 m (both oriented along +x);
// - "bulk": both surfaces; "bottom", "top", "left", "right": the outer boundary.
h = 0.125;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.5, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0.5, 0, h};
Point(7) = {1, 0.5, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {6, 7};
Line(8) = {7, 3};
Curve Loop(1) = {1, 2, -8, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 8, 3, 4, 5};
Plane Surface(2) = {2};
Physical Surface("bulk") = {1, 2};
Physical Curve("weak") = {7};
Physical Curve("strong") = {8};
Physical Curve("bottom") = {1};
Physical Curve("top") = {4};
Physical Curve("left") = {5, 6};
Physical Curve("right") = {2, 3};
