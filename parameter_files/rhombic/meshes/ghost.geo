// A ghost: a round head, straight sides, a zigzag hem and two round eyes.
// Physical Curves: 1 the hem (clamped), 2 the top of the head (pressed),
// 3 the rest of the outline (free), 5 the eyes (the target).
SetFactory("Built-in");
c = Cos(Pi / 3); s = Sin(Pi / 3);
Point(1) = {0, 1.2, 0};
Point(2) = {1, 1.2, 0};
Point(3) = {c, 1.2 + s, 0};
Point(4) = {-c, 1.2 + s, 0};
Point(5) = {-1, 1.2, 0};
Point(6) = {-1, 0, 0};
Point(7) = {-2/3, 0.15, 0};
Point(8) = {-1/3, 0, 0};
Point(9) = {0, 0.15, 0};
Point(10) = {1/3, 0, 0};
Point(11) = {2/3, 0.15, 0};
Point(12) = {1, 0, 0};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Line(4) = {5, 6};
Line(5) = {6, 7};
Line(6) = {7, 8};
Line(7) = {8, 9};
Line(8) = {9, 10};
Line(9) = {10, 11};
Line(10) = {11, 12};
Line(11) = {12, 2};
Curve Loop(1) = {1:11};
// The eyes.
r = 0.15;
For k In {0:1}
  x = -0.35 + 0.7 * k;
  p = newp;
  Point(p) = {x, 1.3, 0};
  Point(p + 1) = {x + r, 1.3, 0};
  Point(p + 2) = {x, 1.3 + r, 0};
  Point(p + 3) = {x - r, 1.3, 0};
  Point(p + 4) = {x, 1.3 - r, 0};
  l = newc;
  Circle(l) = {p + 1, p, p + 2};
  Circle(l + 1) = {p + 2, p, p + 3};
  Circle(l + 2) = {p + 3, p, p + 4};
  Circle(l + 3) = {p + 4, p, p + 1};
  Curve Loop(2 + k) = {l, l + 1, l + 2, l + 3};
  eyes[] += {l, l + 1, l + 2, l + 3};
EndFor
Plane Surface(1) = {1, 2, 3};
Physical Curve(1) = {5:10};
Physical Curve(2) = {2};
Physical Curve(3) = {1, 3, 4, 11};
Physical Curve(5) = {eyes[]};
Physical Surface(1) = {1};
