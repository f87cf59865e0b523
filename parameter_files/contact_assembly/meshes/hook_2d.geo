// A coat hook hung over the top of a door (thesis Fig. 2.20), held by
// contact alone. The door (x in [0, 1], top at y = 0) is the rigid
// obstacle of the hook's flat inner faces (id 4: back leg, top bar, front
// leg). Relief grooves of radius r around the door's two corners (id 2,
// free) keep the hook off them, as a real hook's inner corners do. A coat
// pulls on the middle of the cradle's top (id 3); the other sides (id 2)
// are free.
//   gmsh -2 -format msh2 hook_2d.geo -o hook_2d.msh
DefineConstant[ h = 0.06, r = 0.08 ];
Point(1) = {-0.3, -0.8, 0, h}; Point(2) = {0, -0.8, 0, h};
Point(3) = {0, -r, 0, h/2};    Point(4) = {0, 0, 0, h};
Point(5) = {-r, 0, 0, h/2};    Point(6) = {0, r, 0, h/2};
Point(7) = {r, 0, 0, h/2};     Point(8) = {1 - r, 0, 0, h/2};
Point(9) = {1, 0, 0, h};       Point(10) = {1, r, 0, h/2};
Point(11) = {1 + r, 0, 0, h/2}; Point(12) = {1, -r, 0, h/2};
Point(13) = {1, -2.8, 0, h};   Point(14) = {2.2, -2.8, 0, h};
Point(15) = {2.2, -2.0, 0, h}; Point(16) = {1.9, -2.0, 0, h};
Point(17) = {1.9, -2.5, 0, h}; Point(18) = {1.75, -2.5, 0, h};
Point(19) = {1.45, -2.5, 0, h}; Point(20) = {1.3, -2.5, 0, h};
Point(21) = {1.3, 0.3, 0, h};  Point(22) = {-0.3, 0.3, 0, h};
Line(1) = {1, 2};   Line(2) = {2, 3};
Circle(3) = {3, 4, 5}; Circle(4) = {5, 4, 6}; Circle(5) = {6, 4, 7};
Line(6) = {7, 8};
Circle(7) = {8, 9, 10}; Circle(8) = {10, 9, 11}; Circle(9) = {11, 9, 12};
Line(10) = {12, 13}; Line(11) = {13, 14}; Line(12) = {14, 15};
Line(13) = {15, 16}; Line(14) = {16, 17}; Line(15) = {17, 18};
Line(16) = {18, 19}; Line(17) = {19, 20}; Line(18) = {20, 21};
Line(19) = {21, 22}; Line(20) = {22, 1};
Curve Loop(1) = {1:20};
Plane Surface(1) = {1};
Physical Curve(4) = {2, 6, 10};
Physical Curve(3) = {16};
Physical Curve(2) = {1, 3, 4, 5, 7, 8, 9, 11, 12, 13, 14, 15, 17, 18, 19, 20};
Physical Surface(1) = {1};
