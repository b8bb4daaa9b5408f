"""Python prototypes of the course's algorithms, run before the C++/GLSL chapters.

Each module is also a script (python python_prototypes/NAME.py --help):
  teapot       - tessellate the Newell teapot into an OBJ mesh of any size
  camera_rays  - the pinhole camera convention: one ray per pixel, plus a 3D figure
  obj_io       - a small, strict OBJ reader, the reference for the C++ parser
"""
