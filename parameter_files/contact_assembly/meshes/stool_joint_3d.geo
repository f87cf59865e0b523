// A stool's seat-leg joint (thesis Fig. 2.24, one leg): an MDF seat
// (material 3) rests on a PLA connector (material 1) whose socket holds a
// wooden leg (material 2). The parts share their contact surfaces
// (fragments), so the mesh is conforming across them. Tetrahedra.
// gmsh -3 -format msh2 stool_joint_3d.geo -o stool_joint_3d.msh
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.25 ];
Box(1) = {-1.5, -1.5, 1, 3, 3, 0.3};          // seat
Box(2) = {-0.8, -0.8, 0.2, 1.6, 1.6, 0.8};    // connector block
Cylinder(3) = {0, 0, -2, 0, 0, 2.8, 0.4};     // leg, up to z = 0.8
BooleanDifference(4) = { Volume{2}; Delete; }{ Volume{3}; };
BooleanFragments{ Volume{1, 4, 3}; Delete; }{}
Mesh.MeshSizeMax = h;
e = 1e-6;
Physical Volume(3) = Volume In BoundingBox{-1.5 - e, -1.5 - e, 1 - e, 1.5 + e, 1.5 + e, 1.3 + e};
Physical Volume(1) = Volume In BoundingBox{-0.8 - e, -0.8 - e, 0.2 - e, 0.8 + e, 0.8 + e, 1 + e};
Physical Volume(2) = Volume In BoundingBox{-0.4 - e, -0.4 - e, -2 - e, 0.4 + e, 0.4 + e, 0.8 + e};
// Leg bottom: clamped; seat top: loaded.
Physical Surface(1) = Surface In BoundingBox{-0.4 - e, -0.4 - e, -2 - e, 0.4 + e, 0.4 + e, -2 + e};
Physical Surface(3) = Surface In BoundingBox{-1.5 - e, -1.5 - e, 1.3 - e, 1.5 + e, 1.5 + e, 1.3 + e};
// The connector's free faces (sides and bottom ring): the design surface.
Physical Surface(4) = {
  Surface In BoundingBox{0.8 - e, -0.8 - e, 0.2 - e, 0.8 + e, 0.8 + e, 1 + e},
  Surface In BoundingBox{-0.8 - e, -0.8 - e, 0.2 - e, -0.8 + e, 0.8 + e, 1 + e},
  Surface In BoundingBox{-0.8 - e, 0.8 - e, 0.2 - e, 0.8 + e, 0.8 + e, 1 + e},
  Surface In BoundingBox{-0.8 - e, -0.8 - e, 0.2 - e, 0.8 + e, -0.8 + e, 1 + e},
  Surface In BoundingBox{-0.8 - e, -0.8 - e, 0.2 - e, 0.8 + e, 0.8 + e, 0.2 + e}
};
// Everything else on the outside (seat sides and bottom, the leg's shaft):
// untagged, boundary id 0.
