#pragma once
// Time scales of the contact law in force (the deck's [material] as the stages left it,
// RunContext::contact_law).
#include "granpack/contact/contact_law_params.h"
#include "granpack/io/deck.h"

namespace granpack {

/// Duration of a contact of the smallest grains of the sample (the stiffest, lightest pair)
/// loaded by a force of 5 a^2 P (the tail of the force distribution), as half the period of
/// the linearised normal spring: pi sqrt(m* / K_N). The time step is a fraction of it.
/// m: the contact law's parameters; density: the grains' (kg/m^3).
double contact_duration(const ContactLawParams& m, double density, const SampleSpec& s, int dim,
                        double pressure);

/// Dimensionless stiffness: kappa = (E~/P)^(2/3) for Hertz ([AR] eq. 21), K_N/(a^(dim-2) P)
/// for the linear law ([GRC]: K_N/P in 2D).
double stiffness_number(const ContactLawParams& m, const SampleSpec& s, int dim, double pressure);

} // namespace granpack
