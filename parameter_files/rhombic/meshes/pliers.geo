// Compliant pliers, symmetric about y = 0: two handles (x < 1.6) joined by
// a body to two jaws (x > 2.4). Physical Curves: 1 the upper handle's end,
// 2 the lower handle's end (both moved by the macro problem), 3 free, 4 the
// jaws' inner faces (the target).
SetFactory("Built-in");
Point(1) = {0, -0.75, 0};
Point(2) = {1.6, -0.75, 0};
Point(3) = {2.4, -0.6, 0};
Point(4) = {4, -0.3, 0};
Point(5) = {4, -0.1, 0};
Point(6) = {2.4, -0.1, 0};
Point(7) = {2.4, 0.1, 0};
Point(8) = {4, 0.1, 0};
Point(9) = {4, 0.3, 0};
Point(10) = {2.4, 0.6, 0};
Point(11) = {1.6, 0.75, 0};
Point(12) = {0, 0.75, 0};
Point(13) = {0, 0.25, 0};
Point(14) = {1.6, 0.25, 0};
Point(15) = {1.6, -0.25, 0};
Point(16) = {0, -0.25, 0};
For i In {1:15}
  Line(i) = {i, i + 1};
EndFor
Line(16) = {16, 1};
Curve Loop(1) = {1:16};
Plane Surface(1) = {1};
Physical Curve(1) = {12};
Physical Curve(2) = {16};
Physical Curve(3) = {1, 2, 3, 4, 6, 8, 9, 10, 11, 13, 14, 15};
Physical Curve(4) = {5, 7};
Physical Surface(1) = {1};
