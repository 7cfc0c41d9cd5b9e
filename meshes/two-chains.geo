// Rectangle 2 m x 1 m meshed with linear triangles (T3), with two disjoint straight interfaces
// that each cut a corner block off the bottom of the body; the body above hangs on the two
// blocks only.
// - "left_cut": from (0, 0.3) m to (0.7, 0) m (length sqrt(0.58) = 0.76158 m, sloping 23.2°):
//   it cuts off the triangle (0, 0), (0.7, 0), (0, 0.3) m.
// - "right_cut": from (1.2, 0) m to (2, 0.4) m (length sqrt(0.8) = 0.89443 m, sloping 26.6°):
//   it cuts off the triangle (1.2, 0), (2, 0), (2, 0.4) m.
// - "bulk": the three surfaces; "bottom": the bottoms of the two blocks but for one element
//   length at the cuts (0 <= x <= 0.6 m and 1.3 <= x <= 2 m), so that no node a boundary
//   condition holds is a chain end, whose twins are tied together until the facets at it break;
//   the rest of the bottom is free and in no group; "top", "left", "right": the rest of the outer
//   boundary.
h = 0.1;
Point(1) = {0, 0, 0, h};
Point(2) = {0.6, 0, 0, h};
Point(3) = {0.7, 0, 0, h};
Point(4) = {1.2, 0, 0, h};
Point(5) = {1.3, 0, 0, h};
Point(6) = {2, 0, 0, h};
Point(7) = {2, 0.4, 0, h};
Point(8) = {2, 1, 0, h};
Point(9) = {0, 1, 0, h};
Point(10) = {0, 0.3, 0, h};
Line(1) = {1, 2};    // bottom of the left block, held
Line(2) = {2, 3};    // bottom of the left block, free
Line(3) = {3, 4};    // bottom of the body, free
Line(4) = {4, 5};    // bottom of the right block, free
Line(5) = {5, 6};    // bottom of the right block, held
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 9};
Line(9) = {9, 10};
Line(10) = {10, 1};
Line(11) = {10, 3};  // left_cut
Line(12) = {4, 7};   // right_cut
Curve Loop(1) = {1, 2, -11, 10};
Plane Surface(1) = {1};
Curve Loop(2) = {4, 5, 6, -12};
Plane Surface(2) = {2};
Curve Loop(3) = {11, 3, 12, 7, 8, 9};
Plane Surface(3) = {3};
Physical Surface("bulk") = {1, 2, 3};
Physical Curve("left_cut") = {11};
Physical Curve("right_cut") = {12};
Physical Curve("bottom") = {1, 5};
Physical Curve("top") = {8};
Physical Curve("left") = {9, 10};
Physical Curve("right") = {6, 7};
