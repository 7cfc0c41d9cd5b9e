// Rectangle 2 m x 1 m meshed with linear triangles (T3), cut by an interface with a right-angled
// kink: along y = 0.4 m from x = 0 to 1 m, then up x = 1 m to the top. It cuts off the block
// [0, 1] x [0.4, 1] m from an L-shaped rest.
// - "bulk": both surfaces; "interface": the two legs, one chain;
// - "top": the block's top only (0 <= x <= 1 m, y = 1 m); "bottom", "left", "right".
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {2, 0, 0, h};
Point(3) = {2, 1, 0, h};
Point(4) = {1, 1, 0, h};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0.4, 0, h};
Point(7) = {1, 0.4, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {6, 7};
Line(8) = {7, 4};
Curve Loop(1) = {1, 2, 3, -8, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 8, 4, 5};
Plane Surface(2) = {2};
Physical Surface("bulk") = {1, 2};
Physical Curve("interface") = {7, 8};
Physical Curve("bottom") = {1};
Physical Curve("top") = {4};
Physical Curve("left") = {5, 6};
Physical Curve("right") = {2};
