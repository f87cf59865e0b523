// A disk of radius 1: the bottom arc is clamped (Physical Curve 1), the
// top arc is pressed (2), the sides are free (3).
SetFactory("Built-in");
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {0, 1, 0};
Point(4) = {-1, 0, 0};
Point(5) = {0, -1, 0};
Point(6) = {Cos(Pi/4), Sin(Pi/4), 0};
Point(7) = {-Cos(Pi/4), Sin(Pi/4), 0};
Point(8) = {-Cos(Pi/4), -Sin(Pi/4), 0};
Point(9) = {Cos(Pi/4), -Sin(Pi/4), 0};
Circle(1) = {2, 1, 6};
Circle(2) = {6, 1, 3};
Circle(3) = {3, 1, 7};
Circle(4) = {7, 1, 4};
Circle(5) = {4, 1, 8};
Circle(6) = {8, 1, 5};
Circle(7) = {5, 1, 9};
Circle(8) = {9, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
Physical Curve(1) = {6, 7};
Physical Curve(2) = {2, 3};
Physical Curve(3) = {1, 4, 5, 8};
Physical Surface(1) = {1};
