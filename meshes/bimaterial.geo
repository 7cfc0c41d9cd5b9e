// A bar [0, 2.5] m x [0, 0.06] m of two materials in series along x, meshed with rectangles (Q4):
// - "soft": 0 <= x <= 1 m, elements 0.01 m (x) by 0.015 m (y): h_e = A/l_max = 0.01 m;
// - "stiff": 1 <= x <= 2.5 m, elements 0.015 m by 0.015 m: h_e = 0.015 m;
// - "bar": both surfaces (a group overlapping the two: the scene tests name it to give one
//   element two materials);
// - "joint": the line x = 1 m between them (oriented along +y), a cohesive interface when a
//   scene names it; "bottom", "top", "left", "right": the outer boundary.
// The two element sizes make the stable step of a stiff right part (c_d twice the left's) come
// from its larger elements: h/c_d is smallest there, not where h is.
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {2.5, 0, 0};
Point(4) = {2.5, 0.06, 0};
Point(5) = {1, 0.06, 0};
Point(6) = {0, 0.06, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7};
Plane Surface(2) = {2};
Transfinite Curve{1, 5} = 101;
Transfinite Curve{2, 4} = 101;
Transfinite Curve{3, 6, 7} = 5;
Transfinite Surface{1};
Transfinite Surface{2};
Recombine Surface{1, 2};
Physical Surface("soft") = {1};
Physical Surface("stiff") = {2};
Physical Surface("bar") = {1, 2};
Physical Curve("joint") = {7};
Physical Curve("bottom") = {1, 2};
Physical Curve("top") = {4, 5};
Physical Curve("left") = {6};
Physical Curve("right") = {3};
