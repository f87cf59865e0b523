// A two-part lever (thesis Fig. 2.16): an L-shaped bracket (material 1)
// whose foot is clamped to a table along x in [0, 1] and whose upright
// leans on a rigid wall (x = 3), and an arm (material 2) plugged into a
// slot at the upright's top by a peg; the arm's free end is loaded. The
// bracket and the arm share the slot's walls and bottom and the upright's
// top. Triangles.
// gmsh -2 -format msh2 lever_2d.geo -o lever_2d.msh
DefineConstant[ h = 0.08 ];
Point(1) = {0, 0, 0, h};      Point(2) = {1, 0, 0, h};
Point(3) = {3, 0, 0, h};      Point(4) = {3, 2, 0, h};
Point(5) = {2.75, 2, 0, h};   Point(6) = {2.75, 1.5, 0, h};
Point(7) = {2.45, 1.5, 0, h}; Point(8) = {2.45, 2, 0, h};
Point(9) = {2.2, 2, 0, h};    Point(10) = {2.2, 0.5, 0, h};
Point(11) = {0, 0.5, 0, h};
Point(12) = {3, 2.4, 0, h};   Point(13) = {0.5, 2.4, 0, h};
Point(14) = {0.5, 2, 0, h};
// bracket outline
Line(1) = {1, 2};   Line(2) = {2, 3};   Line(3) = {3, 4};   Line(4) = {4, 5};
Line(5) = {5, 6};   Line(6) = {6, 7};   Line(7) = {7, 8};   Line(8) = {8, 9};
Line(9) = {9, 10};  Line(10) = {10, 11}; Line(11) = {11, 1};
// arm outline (shares 4-5-6-7-8-9 with the bracket)
Line(12) = {4, 12}; Line(13) = {12, 13}; Line(14) = {13, 14};
Line(15) = {14, 9};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
Plane Surface(1) = {1};
Curve Loop(2) = {-8, -7, -6, -5, -4, 12, 13, 14, 15};
Plane Surface(2) = {2};
Physical Curve(1) = {1};                     // foot clamped to the table
Physical Curve(2) = {3};                     // upright against the wall
Physical Curve(3) = {14};                    // arm's loaded end
Physical Curve(4) = {2, 9, 10, 11, 12, 13, 15}; // free
Physical Surface(1) = {1};
Physical Surface(2) = {2};
