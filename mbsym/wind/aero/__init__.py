"""Rotor aerodynamics: steady BEM, performance surfaces, smooth CasADi rotor loads."""
