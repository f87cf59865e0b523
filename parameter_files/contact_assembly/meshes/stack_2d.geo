// Two stacked blocks sharing the line y = 1 (materials 1 and 2), quads.
// gmsh -2 -format msh2 stack_2d.geo -o stack_2d.msh
n = 4;
Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0};
Point(4) = {0, 1, 0}; Point(5) = {2, 2, 0}; Point(6) = {0, 2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {3, 5}; Line(6) = {5, 6}; Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7}; Plane Surface(2) = {2};
Transfinite Curve{1, 3, 6} = 2 * n + 1; Transfinite Curve{2, 4, 5, 7} = n + 1;
Transfinite Surface{1, 2}; Recombine Surface{1, 2};
Physical Curve(2) = {1};      // bottom: on the rigid floor
Physical Curve(4) = {4, 7};   // left: symmetry
Physical Curve(3) = {6};      // top: loaded
Physical Curve(5) = {2, 5};   // right: free
Physical Surface(1) = {1};
Physical Surface(2) = {2};
