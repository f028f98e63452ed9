"""Scene items: one drawable per file, each owning its GL data and state preset.
"""
