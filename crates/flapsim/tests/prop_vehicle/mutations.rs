//! Mutations that must never panic: one to three structural mutations of a base vehicle's
//! TOML tree (replace a value, delete a value or a section, add an unknown field), an unknown
//! field named in its parse error, a number replaced by another type (a parse error), and
//! text-level mutations of the files (truncated, bit-flipped, spliced, random bytes and
//! text).

use flapsim::Error;
use proptest::prelude::*;
use proptest::sample::Index;

use crate::bases::bases_cached;
use crate::checks::{check_error, load_guarded};
use crate::toml_mutation::{
    Mutation, config, mutate_text, mutated, mutation, non_number, repl, replace_numeric_leaf,
    text_mutation,
};

// ---------------------------------------------------------------------------------------------
// Structural mutations of the TOML tree.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(1500))]

    /// One to three structural mutations of a base vehicle: loading never panics and errors
    /// follow the contract.
    #[test]
    fn structural_mutations_never_panic(
        base in any::<Index>(),
        muts in prop::collection::vec(mutation(), 1..4),
    ) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &muts);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)
                .map_err(|f| TestCaseError::fail(format!("{f}\nmutations: {what:?}")))?;
        }
    }
}

proptest! {
    #![proptest_config(config(300))]

    /// An unknown field in any table (root, body, wing.planform, kinematics, sim, ...) is a
    /// parse error naming it.
    #[test]
    fn unknown_fields_are_named(base in any::<Index>(), table in any::<Index>(), r in repl()) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &[Mutation::AddUnknown(table, r)]);
        let e = load_guarded(&text)?.expect_err("unknown field accepted");
        check_error(&e, &text)?;
        prop_assert!(
            matches!(e, Error::Model(wingforce::Error::Parse { .. })),
            "{:?}", what
        );
        prop_assert!(e.to_string().contains("zz_unknown_field"), "{what:?}: {e}");
    }
}

proptest! {
    #![proptest_config(config(400))]

    /// A number replaced by a string, boolean, array or table is a parse error.
    #[test]
    fn type_errors_are_parse_errors(
        base in any::<Index>(),
        leaf in any::<Index>(),
        r in non_number(),
    ) {
        let (path, text) = replace_numeric_leaf(&base.get(bases_cached()).1, leaf, &r);
        let e = load_guarded(&text)?.expect_err(&format!("{path} = {r:?} accepted"));
        check_error(&e, &text)?;
        prop_assert!(
            matches!(e, Error::Model(wingforce::Error::Parse { .. })),
            "{} = {:?}: {}", path, r, e
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Text-level mutations.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(1500))]

    /// Truncated, bit-flipped, spliced, random-byte and random-text files (the real files
    /// with their comments, and the full variant).
    #[test]
    fn text_mutations_never_panic(which in 0usize..4, m in text_mutation()) {
        let base = match which {
            0 => flapsim::DROSOPHILA_TOML.to_owned(),
            1 => flapsim::ROBOBEE_KINEMATIC_TOML.to_owned(),
            2 => flapsim::BUMBLEBEE_TOML.to_owned(),
            _ => toml::to_string(&bases_cached()[3].1).unwrap(),
        };
        let text = mutate_text(&base, &m);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)?;
        }
    }
}
