// Rectangle 2 m x 1 m meshed with linear triangles (T3), cut by a circular-arc interface.
// - "interface": the arc of centre (1, -1.1) m through (0, 0.4) m and (2, 0.4) m, so of radius
//   R = sqrt(1 + 1.5^2) m = 1.80278 m, apex at y = 0.70278 m and length 2 R asin(1/R) = 2.12007 m;
//   oriented from x = 0 to x = 2 (the + side, left of that direction, is the part above the arc).
// - "bulk": both surfaces; "bottom", "top", "left", "right": the outer boundary.
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.4, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0.4, 0, h};
Point(7) = {1, -1.1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Circle(7) = {6, 7, 3};
Curve Loop(1) = {1, 2, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 3, 4, 5};
Plane Surface(2) = {2};
Physical Surface("bulk") = {1, 2};
Physical Curve("interface") = {7};
Physical Curve("bottom") = {1};
Physical Curve("top") = {4};
Physical Curve("left") = {5, 6};
Physical Curve("right") = {2, 3};
