// osd_ref.h — OpenSubdiv topology for a q2n_mesh: the one place the reference programs
// (tests/ref_*.cpp, bench/*.cpp) turn our mesh into a Far::TopologyRefiner.
#ifndef Q2N_TEST_OSD_REF_H
#define Q2N_TEST_OSD_REF_H

#include <vector>

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

extern "C" {
#include "mesh/mesh.h"
}

// Catmull–Clark refiner of m; boundary rule EDGE_AND_CORNER matches q2n_mesh_subdivide
// (valence-2 boundary vertices stay fixed).  NULL on failure; caller deletes.
static inline OpenSubdiv::Far::TopologyRefiner *
osd_refiner_create(const q2n_mesh *m, OpenSubdiv::Sdc::Options::VtxBoundaryInterpolation boundary =
                                          OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER)
{
    using namespace OpenSubdiv;
    std::vector<int> nverts(m->nf);
    for (int f = 0; f < m->nf; f++) nverts[f] = q2n_face_size(m, f);
    Far::TopologyDescriptor desc;
    desc.numVertices = m->nv;
    desc.numFaces = m->nf;
    desc.numVertsPerFace = nverts.data();
    desc.vertIndicesPerFace = m->face_vert;
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(boundary);
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    return Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
}

#endif
