// A 3 x 1 channel with a square obstacle, for `blockmesh convert` (README, "Converting meshes").
// Triangles on the left half, quadrilaterals on the right; physical groups name the boundary.
h = 0.2;
Point(1) = {0, 0, 0, h};   Point(2) = {1.5, 0, 0, h}; Point(3) = {3, 0, 0, h};
Point(4) = {3, 1, 0, h};   Point(5) = {1.5, 1, 0, h}; Point(6) = {0, 1, 0, h};
Point(7) = {0.5, 0.4, 0, h / 2}; Point(8) = {0.8, 0.4, 0, h / 2};
Point(9) = {0.8, 0.6, 0, h / 2}; Point(10) = {0.5, 0.6, 0, h / 2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};
Line(6) = {6, 1}; Line(7) = {2, 5};
Line(8) = {7, 8}; Line(9) = {8, 9}; Line(10) = {9, 10}; Line(11) = {10, 7};
Curve Loop(1) = {1, 7, 5, 6};
Curve Loop(2) = {2, 3, 4, -7};
Curve Loop(3) = {8, 9, 10, 11};
Plane Surface(1) = {1, 3};
Plane Surface(2) = {2};
Recombine Surface {2};
Physical Curve("inlet") = {6};
Physical Curve("outlet") = {3};
Physical Curve("walls") = {1, 2, 4, 5};
Physical Curve("obstacle") = {8, 9, 10, 11};
Physical Surface("upstream") = {1};
Physical Surface("downstream") = {2};
