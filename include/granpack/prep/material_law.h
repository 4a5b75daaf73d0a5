#pragma once
// From the deck's material to the contact law and its time scales.
#include "granpack/contact/contact_law.h"
#include "granpack/io/deck.h"

namespace granpack {

/// The contact law the deck's [material] describes (current values: `set` may change them).
template <int dim> ContactLaw<dim> contact_law_of(const MaterialSpec& m);

/// Duration of a contact of the smallest grains of the sample (the stiffest, lightest pair)
/// loaded by a force of 5 a^2 P (the tail of the force distribution), as half the period of
/// the linearised normal spring: pi sqrt(m* / K_N). The time step is a fraction of it.
double contact_duration(const MaterialSpec& m, const SampleSpec& s, int dim, double pressure);

/// Dimensionless stiffness: kappa = (E~/P)^(2/3) for Hertz ([AR] eq. 21), K_N/(a^(dim-2) P)
/// for the linear law ([GRC]: K_N/P in 2D).
double stiffness_number(const MaterialSpec& m, const SampleSpec& s, int dim, double pressure);

}  // namespace granpack
