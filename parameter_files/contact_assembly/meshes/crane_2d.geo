// A 2D tower crane of four parts (thesis Fig. 2.22): a base (material 1,
// clamped at the bottom, id 1), a lower and an upper mast section
// (materials 2, 3) and a jib (material 4), each held in the part below by
// a peg in a slot. The meshes are conforming; the interfaces 1-2, 2-3, 3-4
// are cut open by the app (Mesh/Separate interfaces). The jib's tip (id 3)
// carries the load, its short end (id 4) a counterweight; id 2 is free.
//   gmsh -2 -format msh2 crane_2d.geo -o crane_2d.msh
DefineConstant[ h = 0.1 ];
Point(1) = {-1, 0, 0, h};      Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h};       Point(4) = {0.5, 1, 0, h};
Point(5) = {0.3, 1, 0, h};     Point(6) = {0.3, 0.5, 0, h};
Point(7) = {-0.3, 0.5, 0, h};  Point(8) = {-0.3, 1, 0, h};
Point(9) = {-0.5, 1, 0, h};    Point(10) = {-1, 1, 0, h};
Point(11) = {0.5, 4, 0, h};    Point(12) = {0.25, 4, 0, h};
Point(13) = {0.25, 3.6, 0, h}; Point(14) = {-0.25, 3.6, 0, h};
Point(15) = {-0.25, 4, 0, h};  Point(16) = {-0.5, 4, 0, h};
Point(17) = {0.5, 6.5, 0, h};  Point(18) = {0.25, 6.5, 0, h};
Point(19) = {0.25, 6.1, 0, h}; Point(20) = {-0.25, 6.1, 0, h};
Point(21) = {-0.25, 6.5, 0, h}; Point(22) = {-0.5, 6.5, 0, h};
Point(23) = {5, 6.5, 0, h};    Point(24) = {5, 7.3, 0, h};
Point(25) = {4.6, 7.3, 0, h};  Point(26) = {-1.6, 7.3, 0, h};
Point(27) = {-2, 7.3, 0, h};   Point(28) = {-2, 6.5, 0, h};
// base
Line(1) = {1, 2};   Line(2) = {2, 3};   Line(3) = {3, 4};   Line(4) = {4, 5};
Line(5) = {5, 6};   Line(6) = {6, 7};   Line(7) = {7, 8};   Line(8) = {8, 9};
Line(9) = {9, 10};  Line(10) = {10, 1};
// lower mast
Line(11) = {4, 11};  Line(12) = {11, 12}; Line(13) = {12, 13};
Line(14) = {13, 14}; Line(15) = {14, 15}; Line(16) = {15, 16};
Line(17) = {16, 9};
// upper mast
Line(18) = {11, 17}; Line(19) = {17, 18}; Line(20) = {18, 19};
Line(21) = {19, 20}; Line(22) = {20, 21}; Line(23) = {21, 22};
Line(24) = {22, 16};
// jib
Line(25) = {17, 23}; Line(26) = {23, 24}; Line(27) = {24, 25};
Line(28) = {25, 26}; Line(29) = {26, 27}; Line(30) = {27, 28};
Line(31) = {28, 22};
Curve Loop(1) = {1:10};
Curve Loop(2) = {-8, -7, -6, -5, -4, 11, 12, 13, 14, 15, 16, 17};
Curve Loop(3) = {-16, -15, -14, -13, -12, 18, 19, 20, 21, 22, 23, 24};
Curve Loop(4) = {-23, -22, -21, -20, -19, 25, 26, 27, 28, 29, 30, 31};
For i In {1:4}
  Plane Surface(i) = {i};
  Physical Surface(i) = {i};
EndFor
Physical Curve(1) = {1};
Physical Curve(3) = {27};
Physical Curve(4) = {29};
Physical Curve(2) = {2, 3, 9, 10, 11, 17, 18, 24, 25, 26, 28, 30, 31};
