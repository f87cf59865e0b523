// An L-shaped bracket (thesis Fig. 2.16, lever-like): the foot rests on a
// table, clamped along x in [0, 1]; the upright's outer side leans on a
// rigid wall (x = 3). Triangles.
// gmsh -2 -format msh2 bracket_2d.geo -o bracket_2d.msh
DefineConstant[ h = 0.08 ];
Point(1) = {0, 0, 0, h};   Point(2) = {1, 0, 0, h};   Point(3) = {3, 0, 0, h};
Point(4) = {3, 2, 0, h};   Point(5) = {2.5, 2, 0, h}; Point(6) = {2.5, 0.5, 0, h};
Point(7) = {0, 0.5, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7};
Plane Surface(1) = {1};
Physical Curve(1) = {1};          // clamped on the table
Physical Curve(2) = {3};          // against the rigid wall
Physical Curve(3) = {4};          // loaded
Physical Curve(4) = {2, 5, 6, 7}; // free
Physical Surface(1) = {1};
