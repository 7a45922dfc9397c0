//! Shell-style patterns for file names, as a user writes them in a suite spec (`*shape=hex*`) or on
//! the command line (`--recording 'push_00?.csv'`): one matcher for both.

/// Whether `text` matches `pattern` whole, where `*` matches any run of characters (none too) and
/// `?` any one. Greedy with backtracking to the last `*`: linear in practice, never exponential.
pub fn wildcard_match(pattern: &str, text: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), text.chars().collect());
    let (mut pi, mut ti) = (0, 0);
    let (mut star, mut mark) = (None, 0);
    while ti < t.len() {
        if pi < p.len() && (p[pi] == '?' || p[pi] == t[ti]) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == '*' {
            star = Some(pi);
            mark = ti;
            pi += 1;
        } else if let Some(s) = star {
            pi = s + 1;
            mark += 1;
            ti = mark;
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards_match_whole_names_like_a_shell() {
        assert!(wildcard_match(
            "*shape=hex*",
            "motion_surface=abs_shape=hex_a=0.h5"
        ));
        assert!(!wildcard_match(
            "*shape=hex*",
            "motion_surface=abs_shape=rect1.h5"
        ));
        assert!(wildcard_match("push_0?.csv", "push_07.csv"));
        assert!(!wildcard_match("push_0?.csv", "push_107.csv"));
        assert!(wildcard_match("*", ""));
        assert!(wildcard_match("*.csv", "a.csv"));
        assert!(wildcard_match("push_*", "push_"));
        assert!(!wildcard_match("push", "push_000.csv"));
        assert!(wildcard_match("a*b*c", "aXXbYc"));
        assert!(!wildcard_match("a*b*c", "aXXbY"));
        assert!(
            wildcard_match("a*b*c", "abcbc"),
            "backtracks to the last star"
        );
    }
}
