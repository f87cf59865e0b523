// A two-part bridge (thesis Fig. 2.18, Table 2.2 "Bridge": Dirichlet + RD
// + DD + traction): a deck of two spans joined at mid-span by a peg of the
// left span in a slot of the right one. The left span is built into the
// left abutment (clamped end face); the right span rests on the right
// abutment (a rigid support under its end). The deck's top carries the
// load. The parts share the joint's faces. Triangles.
// gmsh -2 -format msh2 bridge_2d.geo -o bridge_2d.msh
DefineConstant[ h = 0.08 ];
// left span (material 1) with its peg
Point(1) = {0, 0, 0, h};      Point(2) = {3, 0, 0, h};
Point(3) = {3, 0.2, 0, h};    Point(4) = {3.4, 0.2, 0, h};
Point(5) = {3.4, 0.45, 0, h}; Point(6) = {3, 0.45, 0, h};
Point(7) = {3, 0.65, 0, h};   Point(8) = {0, 0.65, 0, h};
// right span (material 2)
Point(9) = {6, 0, 0, h};      Point(10) = {6, 0.65, 0, h};
Point(11) = {5.4, 0, 0, h};
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};  Line(4) = {4, 5};
Line(5) = {5, 6};  Line(6) = {6, 7};  Line(7) = {7, 8};  Line(8) = {8, 1};
Line(9) = {2, 11}; Line(10) = {11, 9}; Line(11) = {9, 10}; Line(12) = {10, 7};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
Curve Loop(2) = {9, 10, 11, 12, -6, -5, -4, -3, -2};
Plane Surface(2) = {2};
Physical Curve(1) = {8};        // left end, built in
Physical Curve(2) = {10};       // right end on the rigid abutment
Physical Curve(3) = {7, 12};    // deck top, loaded
Physical Curve(4) = {1, 9, 11}; // free underside and right end
Physical Surface(1) = {1};
Physical Surface(2) = {2};
