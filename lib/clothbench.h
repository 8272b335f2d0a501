/* clothbench: one include for programs built on the core library. */
#ifndef CLOTHBENCH_H
#define CLOTHBENCH_H

#include "config.h"
#include "definiteness.h"
#include "eigen.h"
#include "energy.h"
#include "experiment.h"
#include "integrator.h"
#include "mesh.h"
#include "outfile.h"
#include "progress.h"
#include "provenance.h"
#include "run.h"
#include "scene.h"
#include "solver.h"
#include "sparse.h"
#include "status.h"
#include "system.h"
#include "topology.h"

#endif
