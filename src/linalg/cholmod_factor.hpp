#pragma once
// The CD0 contact matrix's LDLᵀ factor in CHOLMOD, kept equal to the matrix of the current
// contact set by multiple-rank updates: the one factor behind both the "cholmod" backend and
// the PETSc backend's default preconditioner (a PCSHELL around it).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// A_ii = z_i + δ, A_ij = −1 per contact, as a simplicial LDLᵀ factor:
///  - `analyse` orders (METIS nested dissection, or AMD) the pattern of every candidate pair
///    (the neighbour list, explicit zeros for pairs not touching), so no contact that forms
///    before the next list rebuild needs new fill;
///  - `factorize` computes the numeric factor of a contact set from scratch;
///  - `follow` brings the factor to a new contact set by one multiple-rank update (contacts
///    that formed: A + W Wᵀ, W's columns e_i − e_j) and one downdate (contacts that broke),
///    CHOLMOD's cholmod_updown (Davis and Hager), a pass along the union of the elimination
///    tree paths of the changed rows, 8 columns at a time;
///  - `solve` applies A⁻¹ to both right-hand sides (n × 2, column major) in one pass.
/// Sequential and deterministic (no threads, fixed ordering).
class CholmodUpdatedFactor {
  public:
    enum class Ordering { metis, amd };
    CholmodUpdatedFactor(std::size_t n, double delta, Ordering ordering);
    ~CholmodUpdatedFactor();
    CholmodUpdatedFactor(const CholmodUpdatedFactor&) = delete;
    CholmodUpdatedFactor& operator=(const CholmodUpdatedFactor&) = delete;

    /// Symbolic analysis of the candidate pairs' pattern; drops the numeric factor.
    void analyse(std::span<const ContactPair> pairs);
    /// Numeric factor of the contact set `in_contact` (one flag per pair of `analyse`).
    void factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact);
    /// Updates the factor to `in_contact`; returns the number of contacts formed or broken.
    int follow(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact);
    /// x = A⁻¹ b for b, x of n × 2 (x half then y half); b and x may not overlap.
    void solve(const double* b, double* x);

    bool has_factor() const;
    /// The contacts of the last `factorize` or `follow` (residual check, matrix products).
    std::span<const ContactPair> contacts() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace jamsim::linalg
