// Square 2 m x 2 m meshed with linear triangles (T3), with a circular inclusion of radius
// 0.4 m centred at (1, 1) m whose boundary is a closed interface.
// - "interface": the circle (four quarter arcs), 2 pi 0.4 m = 2.51327 m long;
// - "bulk": the matrix and the inclusion; "bottom", "right", "top", "left": the outer boundary.
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 2, 0, h};
Point(4) = {0, 2, 0, h};
Point(5) = {1, 1, 0, h};
Point(6) = {1.4, 1, 0, h};
Point(7) = {1, 1.4, 0, h};
Point(8) = {0.6, 1, 0, h};
Point(9) = {1, 0.6, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Plane Surface(2) = {2};
Physical Surface("bulk") = {1, 2};
Physical Curve("interface") = {5, 6, 7, 8};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
