// Plate 0.2 m x 0.02 m of linear triangles (T3), unstructured (Gmsh's default 2D algorithm), for
// the P and S wave-arrival tests of the unstructured driver
// (tests/tests/validation/fem_unstructured_waves.rs).
// - "plate": the surface; "left", "right", "top", "bottom": the four sides.
// - Two embedded points on the mid-line, x = 0.05 m and x = 0.15 m, are mesh nodes: the probes.
h = 1e-3;
L = 0.2;
H = 0.02;
Point(1) = {0, 0, 0, h};
Point(2) = {L, 0, 0, h};
Point(3) = {L, H, 0, h};
Point(4) = {0, H, 0, h};
Point(5) = {0.05, H / 2, 0, h};
Point(6) = {0.15, H / 2, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{5, 6} In Surface{1};
Physical Surface("plate") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
