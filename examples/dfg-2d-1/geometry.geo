// DFG benchmark 2D-1 (Schäfer & Turek 1996): a channel [0, 2.2] x [0, 0.41] with a
// cylinder of diameter 0.1 centred at (0.2, 0.2). The starting mesh of the example:
//   gmsh geometry.geo -2 -format msh22 -o start.msh
Point(1) = {0, 0, 0, 0.04}; Point(2) = {2.2, 0, 0, 0.08}; Point(3) = {2.2, 0.41, 0, 0.08};
Point(4) = {0, 0.41, 0, 0.04};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Point(5) = {0.2, 0.2, 0, 0.02};
Point(6) = {0.15, 0.2, 0, 0.02}; Point(7) = {0.2, 0.15, 0, 0.02}; Point(8) = {0.25, 0.2, 0, 0.02};
Point(9) = {0.2, 0.25, 0, 0.02};
Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 8}; Circle(7) = {8, 5, 9}; Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Curve("Inlet", 1) = {4};
Physical Curve("Outlet", 2) = {2};
Physical Curve("Walls", 3) = {1, 3};
Physical Curve("Cylinder", 4) = {5, 6, 7, 8};
Physical Surface("Fluid", 10) = {1};
