// Rectangle 2 m x 1 m meshed with linear triangles (T3).
// - "interface": a straight line y = 0.5 m across the whole width (both ends on the outer boundary),
//   oriented from x = 0 to x = 2, so its + side (left of the direction) is the upper half.
// - "crack": an edge crack along y = 0.25 m from the left side to x = 1 m; its tip is inside the
//   body (a node that the split does not twin).
// - "bulk": both surfaces; "bottom", "top", "left", "right": the outer boundary.
h = 0.125;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.5, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0.5, 0, h};
Point(7) = {0, 0.25, 0, h};
Point(8) = {1, 0.25, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 1};
Line(8) = {6, 3};
Line(9) = {7, 8};
Curve Loop(1) = {1, 2, -8, 6, 7};
Plane Surface(1) = {1};
Curve Loop(2) = {8, 3, 4, 5};
Plane Surface(2) = {2};
Curve{9} In Surface{1};
Physical Surface("bulk") = {1, 2};
Physical Curve("interface") = {8};
Physical Curve("crack") = {9};
Physical Curve("bottom") = {1};
Physical Curve("top") = {4};
Physical Curve("left") = {5, 6, 7};
Physical Curve("right") = {2, 3};
