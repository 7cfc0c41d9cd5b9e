// Rectangle 2 m x 1 m meshed with linear triangles (T3), cut along y = 0.5 m by a cohesive
// interface that ends on both sides, where only the lower half of the left side is a boundary
// curve: the chain's left end is a node of "left" on the lower face only, so a condition that
// holds "left" holds one copy of that end and not its twin (the case of a support that stops
// where an interface meets the boundary).
// - "bulk": both surfaces; "interface": y = 0.5 m, 0 <= x <= 2 m;
// - "bottom", "top", "right" (the whole right side), "left" (0 <= y <= 0.5 m only).
h = 0.125;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.5, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0.5, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {6, 3};
Curve Loop(1) = {1, 2, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 3, 4, 5};
Plane Surface(2) = {2};
Physical Surface("bulk") = {1, 2};
Physical Curve("interface") = {7};
Physical Curve("bottom") = {1};
Physical Curve("top") = {4};
Physical Curve("left") = {6};
Physical Curve("right") = {2, 3};
