// A wall of 9 bricks in 3 courses, 1 m x 0.6 m, meshed with linear triangles (T3, h = 0.04 m),
// every joint between two bricks a cohesive interface: a network of 16 chains meeting at 8 T
// junctions, ending on the outer boundary at 8 points. The course joints are at y = 0.2 and
// 0.4 m; each head joint leans, so that the junction angles are not 90° (bottom -> top x, m):
// lower course 0.179 -> 0.205 and 0.590 -> 0.612, middle 0.410 -> 0.348 and 0.761 -> 0.840,
// upper 0.181 -> 0.168 and 0.640 -> 0.596. The bricks alternate between two materials, "soft"
// and "stiff", like a checkerboard. Groups: "soft", "stiff" (surfaces), "joints" (every
// interface line), "bottom", "top", "left", "right" (the outer boundary).
// The scene tiny-fem-brick-wall.toml runs on it (tests/tests/validation/fem_junction.rs).
// Meshed by: gmsh -2 -format msh41 brick-wall.geo -o brick-wall.msh
h = 0.04;
Point(1) = {0.0, 0.0, 0, h};
Point(2) = {0.179, 0.0, 0, h};
Point(3) = {0.205, 0.2, 0, h};
Point(4) = {0.0, 0.2, 0, h};
Point(5) = {0.59, 0.0, 0, h};
Point(6) = {0.612, 0.2, 0, h};
Point(7) = {0.41, 0.2, 0, h};
Point(8) = {1.0, 0.0, 0, h};
Point(9) = {1.0, 0.2, 0, h};
Point(10) = {0.761, 0.2, 0, h};
Point(11) = {0.348, 0.4, 0, h};
Point(12) = {0.181, 0.4, 0, h};
Point(13) = {0.0, 0.4, 0, h};
Point(14) = {0.84, 0.4, 0, h};
Point(15) = {0.64, 0.4, 0, h};
Point(16) = {1.0, 0.4, 0, h};
Point(17) = {0.168, 0.6, 0, h};
Point(18) = {0.0, 0.6, 0, h};
Point(19) = {0.596, 0.6, 0, h};
Point(20) = {1.0, 0.6, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {2, 5};
Line(6) = {5, 6};
Line(7) = {6, 7};
Line(8) = {7, 3};
Line(9) = {5, 8};
Line(10) = {8, 9};
Line(11) = {9, 10};
Line(12) = {10, 6};
Line(13) = {7, 11};
Line(14) = {11, 12};
Line(15) = {12, 13};
Line(16) = {13, 4};
Line(17) = {10, 14};
Line(18) = {14, 15};
Line(19) = {15, 11};
Line(20) = {9, 16};
Line(21) = {16, 14};
Line(22) = {12, 17};
Line(23) = {17, 18};
Line(24) = {18, 13};
Line(25) = {15, 19};
Line(26) = {19, 17};
Line(27) = {16, 20};
Line(28) = {20, 19};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8, -2};
Plane Surface(2) = {2};
Curve Loop(3) = {9, 10, 11, 12, -6};
Plane Surface(3) = {3};
Curve Loop(4) = {-3, -8, 13, 14, 15, 16};
Plane Surface(4) = {4};
Curve Loop(5) = {-7, -12, 17, 18, 19, -13};
Plane Surface(5) = {5};
Curve Loop(6) = {-11, 20, 21, -17};
Plane Surface(6) = {6};
Curve Loop(7) = {-15, 22, 23, 24};
Plane Surface(7) = {7};
Curve Loop(8) = {-14, -19, 25, 26, -22};
Plane Surface(8) = {8};
Curve Loop(9) = {-18, -21, 27, 28, -25};
Plane Surface(9) = {9};
Physical Surface("soft") = {1, 3, 5, 7, 9};
Physical Surface("stiff") = {2, 4, 6, 8};
Physical Curve("joints") = {2, 3, 6, 7, 8, 11, 12, 13, 14, 15, 17, 18, 19, 21, 22, 25};
Physical Curve("bottom") = {1, 5, 9};
Physical Curve("top") = {23, 26, 28};
Physical Curve("left") = {4, 16, 24};
Physical Curve("right") = {10, 20, 27};
