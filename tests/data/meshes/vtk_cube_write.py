# Writes the Gmsh cube (ref22.msh: 339 nodes, 540 triangles, 1125 tetrahedra) with the VTK
# library's own XML writer in four of its encodings, plus 3 vertex cells and a point array
# that the reader must skip, and an Int32 cell array "region" (tets 7, triangles 1, vertices 0).
import vtk
# ref22.msh: gmsh -3 gmsh_cube.geo -format msh22 -o ref22.msh
lines = open('ref22.msh').read().split('\n')
i = lines.index('$Nodes'); n = int(lines[i+1])
pts = vtk.vtkPoints(); pts.SetDataTypeToDouble()
tag = {}
for k in range(n):
    t, x, y, z = lines[i+2+k].split(); tag[int(t)] = k; pts.InsertNextPoint(float(x), float(y), float(z))
j = lines.index('$Elements'); m = int(lines[j+1])
grid = vtk.vtkUnstructuredGrid(); grid.SetPoints(pts)
region = vtk.vtkIntArray(); region.SetName('region')
for k in range(m):
    f = lines[j+2+k].split(); typ = int(f[1]); nt = int(f[2]); nodes = [tag[int(v)] for v in f[3+nt:]]
    if typ == 4: grid.InsertNextCell(10, 4, nodes); region.InsertNextValue(7)
    elif typ == 2: grid.InsertNextCell(5, 3, nodes); region.InsertNextValue(1)
for v in (0, 1, 2):
    grid.InsertNextCell(1, 1, [v]); region.InsertNextValue(0)
grid.GetCellData().AddArray(region)
temp = vtk.vtkDoubleArray(); temp.SetName('temperature')
for k in range(n): temp.InsertNextValue(k * 0.5)
grid.GetPointData().AddArray(temp)
def write(name, mode, compress, header64, big, encode=True):
    w = vtk.vtkXMLUnstructuredGridWriter(); w.SetInputData(grid); w.SetFileName(name)
    {'binary': w.SetDataModeToBinary, 'appended': w.SetDataModeToAppended, 'ascii': w.SetDataModeToAscii}[mode]()
    if compress: w.SetCompressorTypeToZLib()
    else: w.SetCompressorTypeToNone()
    if header64: w.SetHeaderTypeToUInt64()
    else: w.SetHeaderTypeToUInt32()
    if big: w.SetByteOrderToBigEndian()
    else: w.SetByteOrderToLittleEndian()
    w.SetEncodeAppendedData(encode)
    assert w.Write() == 1
write('vtk_cube_binary_zlib_uint64.vtu', 'binary', True, True, False)
write('vtk_cube_binary_uint32_big_endian.vtu', 'binary', False, False, True)
write('vtk_cube_appended_raw_zlib_uint64.vtu', 'appended', True, True, False, encode=False)
write('vtk_cube_appended_base64_uint32.vtu', 'appended', False, False, False, encode=True)
print(grid.GetNumberOfPoints(), grid.GetNumberOfCells())
