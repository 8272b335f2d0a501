/* clothbench: one include for the core library's public API.
 *
 * The core (this folder) is the simulation: meshes, the model and its energy
 * terms, the system, the implicit-Euler objective, integrators, linear
 * solvers and scenes. It knows nothing of configs. The config layer
 * (lib/config/: the INI key table and its binding to core structs), the
 * measurement instruments (lib/instruments/) and the I/O that programs share
 * (lib/io/) sit above it and have their own headers. */
#ifndef CLOTHBENCH_H
#define CLOTHBENCH_H

#include "broadphase.h"
#include "contact.h"
#include "definiteness.h"
#include "eigen.h"
#include "energy.h"
#include "integrator.h"
#include "intersect.h"
#include "material.h"
#include "mesh.h"
#include "objective.h"
#include "projection.h"
#include "response.h"
#include "run.h"
#include "scene.h"
#include "solver.h"
#include "solver_shift.h"
#include "sparse.h"
#include "status.h"
#include "stencil.h"
#include "system.h"
#include "timer.h"
#include "topology.h"

#endif
